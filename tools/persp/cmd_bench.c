#include "cli.h"

int cmd_bench(int argc, char **argv)
{
    (void)argc, (void)argv;
    return cli_error(CLI_FAIL, "bench: this command is not available yet");
}
