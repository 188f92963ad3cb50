#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static const struct {
    const char *name;
    int (*run)(int, char **);
    const char *summary;
} commands[] = {
    {"render", cmd_render, "render a built-in scene or a scene file to a PNG or JPEG"},
    {"methods", cmd_methods, "list the texture-coordinate methods"},
    {"accuracy", cmd_accuracy, "measure methods against the exact reference"},
    {"bench", cmd_bench, "measure fill rate, optionally against Mesa llvmpipe"},
    {"merge", cmd_merge, "combine the JSON slices of a sharded accuracy sweep"},
    {"report", cmd_report, "the whole study as one web page"},
    {"vectors", cmd_vectors, "test vectors of midpoint:int for simulating a hardware design"},
    {"view", cmd_view, "interactive side-by-side viewer; --play renders camera paths"},
};

static void usage(FILE *out)
{
    fprintf(out, "usage: persp COMMAND [OPTIONS]\n\n"
                 "persp renders and measures perspective-correct texturing, shading and\n"
                 "filtering methods.\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n  persp COMMAND --help   options of one command\n"
                 "  persp --version        print the version\n");
}

int cli_is_builtin(const char *name)
{
    for (size_t i = 0; i < persp_builtin_scene_count(); i++)
        if (!strcmp(name, persp_builtin_scene_name(i))) return 1;
    return 0;
}

int cli_check_scene(const char *command, const char *name)
{
    if (cli_is_builtin(name) || access(name, F_OK) == 0) return CLI_OK;
    const int err = errno;
    char names[256] = "";
    for (size_t i = 0; i < persp_builtin_scene_count(); i++) {
        size_t used = strlen(names);
        snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "", persp_builtin_scene_name(i));
    }
    return cli_error(CLI_FAIL, "%s: '%s' is neither a built-in scene (%s) nor a file: %s", command, name, names,
                     strerror(err));
}

int cli_replace_texture(persp_context *ctx, persp_scene *scene, const char *path)
{
    persp_image tex;
    persp_status st = persp_image_load(ctx, path, &tex);
    if (st != PERSP_OK) return cli_status(ctx, st, path);
    st = persp_scene_set_texture(scene, &tex);
    persp_image_free(ctx, &tex);
    if (st != PERSP_OK) return cli_status(ctx, st, path);
    persp_scene_info info;
    persp_scene_get_info(scene, &info);
    if (info.filter_count == 0) {
        char message[1200];
        snprintf(message, sizeof message, "--texture %s: the scene has no textured object; nothing was replaced",
                 path);
        cli_warning(NULL, message);
    }
    return CLI_OK;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Output that never reached its file is a failure, as with coreutils'
 * close_stdout: stdio reports a full disk or a closed pipe only when the
 * buffer is flushed, often after the command has returned. A command that
 * already failed has said why; only a success is turned into one. */
static int finish_stdout(const char *command, int rc)
{
    errno = 0;
    int failed = fflush(stdout) != 0 || ferror(stdout);
    int err = errno;
    if (fclose(stdout) != 0 && !failed) failed = 1, err = errno;
    if (failed && rc == CLI_OK)
        rc = cli_error(CLI_FAIL, "%s%swrite error on standard output%s%s", command ? command : "",
                       command ? ": " : "", err ? ": " : "", err ? strerror(err) : "");
    return rc;
}

int main(int argc, char **argv)
{
    cli_install_signal_handlers();
    if (argc < 2) {
        usage(stderr);
        return CLI_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return finish_stdout(NULL, CLI_OK);
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version")) {
        printf("persp %s\n", persp_version());
        return finish_stdout(NULL, CLI_OK);
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (!strcmp(argv[1], commands[i].name))
            return finish_stdout(commands[i].name, commands[i].run(argc - 1, argv + 1));
    cli_error(CLI_USAGE, "unknown command '%s'", argv[1]);
    usage(stderr);
    return CLI_USAGE;
}
