/* persp report: placeholder until the page writer lands. */
#include "cli.h"

int cmd_report(int argc, char **argv)
{
    (void)argc, (void)argv;
    return cli_error(CLI_USAGE, "report: not built");
}
