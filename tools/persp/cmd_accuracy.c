#include "cli.h"

int cmd_accuracy(int argc, char **argv)
{
    (void)argc, (void)argv;
    return cli_error(CLI_FAIL, "accuracy: this command is not available yet");
}
