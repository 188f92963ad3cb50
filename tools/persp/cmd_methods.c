#include "cli.h"

#include <string.h>

int cmd_methods(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            printf("usage: persp methods\n\nLists every texture-coordinate method: name and "
                   "parameters, summary,\nsource section and cost per pixel / span.\n");
            return CLI_OK;
        }
        return cli_error(CLI_USAGE, "methods: unknown option '%s'", argv[i]);
    }
    persp_method_info info;
    for (size_t i = 0; persp_method_get(i, &info) == PERSP_OK; i++) {
        char name[64];
        snprintf(name, sizeof name, "%s%s%s", info.name, info.params[0] ? ":" : "", info.params);
        printf("%-24s %s\n%-24s   source: %s\n%-24s   cost:   %s\n", name, info.summary, "",
               info.source, "", info.cost);
    }
    return CLI_OK;
}
