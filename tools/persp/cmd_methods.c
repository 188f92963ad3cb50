#include "options.h"

#include <string.h>

static void methods_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp methods\n\nLists every texture-coordinate method: name and "
                 "parameters, summary,\nsource and cost per pixel / span. A source is a "
                 "citation key and a section;\nthe keys (e.g. [Romanyuk-PCF]) are defined in "
                 "docs/SOURCES.md.\n\noptions:\n");
    cli_print_options(out, cmd);
}

int cmd_methods(int argc, char **argv)
{
    cli_option opts[] = {CLI_OPT_NO_DEST(cli_opt_help)};
    cli_command cmd = {"methods", "persp methods --help", NULL, opts, sizeof opts / sizeof opts[0], NULL, 0, 0, NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, methods_usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    persp_method_info info;
    for (size_t i = 0; persp_method_get(i, &info) == PERSP_OK; i++) {
        char name[64];
        snprintf(name, sizeof name, "%s%s%s", info.name, info.params[0] ? ":" : "", info.params);
        /* Long parameter lists get a line of their own so the columns stay aligned. */
        if (strlen(name) < 24) printf("%-24s %s\n", name, info.summary);
        else printf("%s\n%-24s %s\n", name, "", info.summary);
        printf("%-24s   source: %s\n%-24s   cost:   %s\n", "", info.source, "", info.cost);
    }
    return CLI_OK;
}

int cli_check_method(const char *command, const char *spec)
{
    persp_status st = persp_method_check(spec);
    if (st == PERSP_OK) return CLI_OK;
    if (st == PERSP_ERR_NOT_FOUND)
        return cli_error(CLI_USAGE, "%s: unknown method '%s' (see persp methods)", command, spec);
    size_t len = strcspn(spec, ":");
    persp_method_info info;
    for (size_t i = 0; persp_method_get(i, &info) == PERSP_OK; i++) {
        if (strlen(info.name) != len || strncmp(info.name, spec, len) != 0) continue;
        if (!info.params[0])
            return cli_error(CLI_USAGE, "%s: bad parameters in method '%s' (%s takes none)", command,
                             spec, info.name);
        return cli_error(CLI_USAGE, "%s: bad parameters in method '%s' (expected %s:%s)", command,
                         spec, info.name, info.params);
    }
    return cli_error(CLI_USAGE, "%s: bad method '%s' (see persp methods)", command, spec);
}
