/*
 * The skeleton every command that works through the library shares: the
 * context from the common options, the sinks for its warnings and its
 * temporary files, the report output, the status messages and the
 * clean-up. One place, so that no command loses the library's warnings
 * (a model whose material file is missing) or leaves a half-written
 * report behind.
 */
#include "options.h"

#include <string.h>

/* Every command that loads a scene or model takes --any-folder: a file
 * refused for lying outside the loaded file's folder says how to allow it. */
static const char *folder_hint(const char *message)
{
    return message && strstr(message, "outside the folder") ? "; --any-folder allows files outside it" : "";
}

void cli_warning(void *user, const char *message)
{
    (void)user;
    fprintf(stderr, "persp: warning: %s%s\n", message, folder_hint(message));
}

/* Whether detail starts with what and a colon; a line break in what stands
 * for the space the library writes for it in a detail. */
static int starts_with_name(const char *detail, const char *what)
{
    size_t i = 0;
    for (; what[i]; i++)
        if (detail[i] != (what[i] == '\n' || what[i] == '\r' ? ' ' : what[i])) return 0;
    return detail[i] == ':';
}

int cli_status(persp_context *ctx, persp_status st, const char *what)
{
    const char *detail = ctx ? persp_context_error(ctx) : "";
    /* Library details start with the file they concern; do not name it twice. */
    const int same = detail && starts_with_name(detail, what);
    /* The status of a refused file is an I/O error, which reads as a
     * failing disk: the hint replaces it. */
    const char *hint = folder_hint(detail);
    const char *kind = hint[0] ? "refused" : persp_status_string(st);
    /* An I/O failure's detail already gives the system's reason ("cannot
     * open: No such file or directory"), which "(input/output error)"
     * after it would contradict. */
    if (st == PERSP_ERR_IO && !hint[0]) {
        if (same) return cli_error(CLI_FAIL, "%s", detail);
        if (detail && detail[0]) return cli_error(CLI_FAIL, "%s: %s", what, detail);
    }
    if (same) return cli_error(CLI_FAIL, "%s (%s%s)", detail, kind, hint);
    if (detail && detail[0]) return cli_error(CLI_FAIL, "%s: %s (%s%s)", what, detail, kind, hint);
    return cli_error(CLI_FAIL, "%s: %s", what, persp_status_string(st));
}

int cli_run(const cli_run_desc *d, cli_body body, void *user)
{
    persp_context *ctx = NULL;
    persp_context_desc cd = {.threads = d->threads, .max_memory = cli_max_memory(d->max_memory), .simd = d->simd};
    persp_status st = persp_context_create(&cd, &ctx);
    if (st == PERSP_ERR_UNSUPPORTED && d->simd != PERSP_SIMD_AUTO)
        return cli_error(CLI_FAIL, "%s: this CPU cannot run --simd %s", d->command, persp_simd_name(d->simd));
    if (st != PERSP_OK) {
        char what[128];
        snprintf(what, sizeof what, "%s: context", d->command);
        return cli_status(NULL, st, what);
    }
    persp_context_set_warning_handler(ctx, cli_warning, NULL);
    persp_context_set_temp_file_handler(ctx, cli_temp_file, NULL);
    cli_output out;
    cli_cap cap;
    memset(&out, 0, sizeof out);
    memset(&cap, 0, sizeof cap);
    int rc = CLI_OK;
    if (d->report) rc = cli_output_open(d->command, d->output, &out);
    if (rc == CLI_OK && d->report && d->output_limit) {
        if ((rc = cli_cap_begin(d->command, &out, &cap, d->output_limit)) != CLI_OK)
            cli_output_close(d->command, &out, 0);
    }
    if (rc == CLI_OK) {
        rc = body(ctx, d->report ? &out : NULL, user);
        int cap_rc = cli_cap_end(d->command, &out, &cap, d->limit_option ? d->limit_option : "the output limit",
                                 rc == CLI_OK);
        if (rc == CLI_OK) rc = cap_rc;
        if (d->report) {
            int out_rc = cli_output_close(d->command, &out, rc == CLI_OK);
            if (rc == CLI_OK) rc = out_rc;
        }
    }
    persp_context_destroy(ctx);
    return rc;
}
