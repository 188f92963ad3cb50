/* persp merge: the JSON slices of `persp accuracy --shard K/N --json` back into one result. */
#include "options.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_SHARDS 4096

static void merge_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp merge [options] FILE...\n\n"
                 "Combines the JSON files of `persp accuracy --shard K/N --json` (all N of\n"
                 "one sweep, in any order) into the JSON the same command without --shard\n"
                 "writes, byte for byte: every row is measured whole by one slice, so no\n"
                 "statistic is approximated. A missing shard is named (\"missing shard 2\n"
                 "of 4\"); shards of another sweep, malformed files and an output that\n"
                 "is one of the inputs are refused before anything is written.\n\noptions:\n");
    cli_print_options(out, cmd);
}

int cmd_merge(int argc, char **argv)
{
    const char *operands[MAX_SHARDS], *output = NULL;
    persp_report_format format = PERSP_REPORT_JSON;
    size_t max_memory = 0;
    cli_option opts[] = {
        CLI_OPT_HELP(cli_opt_output, &output,
                     "write the merged JSON to FILE (default, and -: standard output)"),
        CLI_OPT_HELP(cli_opt_csv, &format, "CSV instead of JSON"),
        CLI_OPT(cli_opt_max_memory, &max_memory),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {"merge",  "persp merge --help", NULL, opts,  sizeof opts / sizeof opts[0],
                       operands, MAX_SHARDS,           0,    "FILE"};
    int rc = cli_parse_or_usage(&cmd, argc, argv, merge_usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    size_t n = cmd.operand_count;
    if (!n) return cli_error(CLI_USAGE, "merge: no files (see persp merge --help)");

    /* Writing over a shard would lose it whatever the merge then does, so
     * an output that is one of the inputs (the same name, or another name
     * of the same file) is refused before anything is read or written. */
    struct stat osb;
    int out_exists = output && strcmp(output, "-") && stat(output, &osb) == 0;
    for (size_t i = 0; output && strcmp(output, "-") && i < n; i++) {
        struct stat isb;
        if (!strcmp(output, operands[i]) ||
            (out_exists && stat(operands[i], &isb) == 0 && isb.st_dev == osb.st_dev &&
             isb.st_ino == osb.st_ino))
            return cli_error(CLI_USAGE, "merge: -o '%s' is also input %zu ('%s'); write the merged "
                                        "file elsewhere (nothing written)",
                             output, i + 1, operands[i]);
    }

    persp_context *ctx = NULL;
    persp_context_desc cd = {.max_memory = cli_max_memory(max_memory)};
    persp_status st = persp_context_create(&cd, &ctx);
    if (st != PERSP_OK) return cli_status(NULL, st, "merge: context");
    persp_context_set_temp_file_handler(ctx, cli_temp_file, NULL);
    persp_accuracy_result **parts = calloc(n, sizeof *parts), *merged = NULL;
    if (!parts) {
        persp_context_destroy(ctx);
        return cli_error(CLI_FAIL, "merge: out of memory");
    }
    rc = CLI_OK;
    for (size_t i = 0; i < n && rc == CLI_OK; i++)
        if ((st = persp_accuracy_read(ctx, operands[i], &parts[i])) != PERSP_OK)
            rc = cli_status(ctx, st, operands[i]);
    if (rc == CLI_OK && (st = persp_accuracy_merge(ctx, (const persp_accuracy_result *const *)parts,
                                                   n, &merged)) != PERSP_OK)
        rc = cli_status(ctx, st, "merge");
    cli_output out = {0};
    if (rc == CLI_OK && (rc = cli_output_open("merge", output, &out)) == CLI_OK) {
        if ((st = persp_accuracy_write(ctx, merged, format, out.f)) != PERSP_OK)
            rc = cli_error(CLI_FAIL, "merge: cannot write '%s': %s", output ? output : "-",
                           persp_context_error(ctx));
        int out_rc = cli_output_close("merge", &out, rc == CLI_OK);
        if (rc == CLI_OK) rc = out_rc;
    }
    persp_accuracy_destroy(merged);
    for (size_t i = 0; i < n; i++)
        persp_accuracy_destroy(parts[i]);
    free(parts);
    persp_context_destroy(ctx);
    return rc;
}
