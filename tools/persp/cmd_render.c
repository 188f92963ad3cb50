#include "cli.h"

int cmd_render(int argc, char **argv)
{
    (void)argc, (void)argv;
    return cli_error(CLI_FAIL, "render: this command is not available yet");
}
