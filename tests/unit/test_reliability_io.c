/*
 * Files, output and parsing (docs/RELIABILITY.md): what a scene may read,
 * how messages quote foreign text, how outputs replace files, strict method
 * parameters, out-of-memory in the JSON parser, paletted PNGs with indices
 * past the palette, and opaque output for translucent textures.
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include "support.h"

#include "core/internal.h"
#include "model/model.h"
#include "io/text.h"

#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[256];

static int setup_dir(void **state)
{
    (void)state;
    return test_tmpdir_make(dir, sizeof dir, "reliability-io");
}

static int remove_dir(void **state)
{
    (void)state;
    return test_tmpdir_remove(dir);
}

static void path_in(char *buf, size_t size, const char *name)
{
    snprintf(buf, size, "%s/%s", dir, name);
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

static void copy_source(const char *rel, const char *to)
{
    char from[1024];
    test_source_path(from, sizeof from, rel);
    FILE *in = fopen(from, "rb"), *out = fopen(to, "wb");
    assert_non_null(in);
    assert_non_null(out);
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        assert_int_equal(fwrite(buf, 1, n, out), n);
    fclose(in);
    assert_int_equal(fclose(out), 0);
}

/* ------------------------------------------------------------ file access */

static const char scene_fmt[] =
    "{\"materials\": {\"m\": {\"texture\": \"%s\"}},\n"
    " \"objects\": [{\"mesh\": \"plane\", \"material\": \"m\"}]}\n";

static persp_status load_scene_naming(persp_context *ctx, const char *texture, persp_toggle any)
{
    char sub[512], scene[600], text[1200];
    path_in(sub, sizeof sub, "scene");
    mkdir(sub, 0777);
    snprintf(scene, sizeof scene, "%s/s.json", sub);
    snprintf(text, sizeof text, scene_fmt, texture);
    write_text(scene, text);
    persp_scene_load_desc desc = {.any_folder = any};
    persp_scene *s = NULL;
    persp_status st = persp_scene_load_ex(ctx, scene, &desc, &s);
    persp_scene_destroy(s);
    return st;
}

static void test_scene_reads_only_its_folder(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char tex[512], inner[512], link[512];
    path_in(tex, sizeof tex, "outside.png");
    copy_source("scenes/textures/checker.png", tex);
    path_in(inner, sizeof inner, "scene/in");
    path_in(link, sizeof link, "scene");
    mkdir(link, 0777);
    mkdir(inner, 0777);
    char inside[600];
    snprintf(inside, sizeof inside, "%s/t.png", inner);
    copy_source("scenes/textures/checker.png", inside);
    /* Inside, through a subfolder and through ".." that comes back in. */
    assert_int_equal(load_scene_naming(ctx, "in/t.png", PERSP_TOGGLE_DEFAULT), PERSP_OK);
    assert_int_equal(load_scene_naming(ctx, "in/../in/t.png", PERSP_TOGGLE_DEFAULT), PERSP_OK);
    /* Outside: "..", an absolute path, a link inside pointing out. */
    const char *refused[] = {"../outside.png", tex, "up/outside.png"};
    snprintf(link, sizeof link, "%s/scene/up", dir);
    assert_int_equal(symlink("..", link), 0);
    for (size_t i = 0; i < 3; i++) {
        assert_int_equal(load_scene_naming(ctx, refused[i], PERSP_TOGGLE_DEFAULT), PERSP_ERR_IO);
        const char *e = persp_context_error(ctx);
        if (!strstr(e, "s.json:1:") || !strstr(e, "is outside the folder"))
            fail_msg("%s: %s", refused[i], e);
        /* ON lifts the restriction. */
        assert_int_equal(load_scene_naming(ctx, refused[i], PERSP_TOGGLE_ON), PERSP_OK);
    }
    /* persp_scene_load is the restricted default. */
    char scene[600];
    snprintf(scene, sizeof scene, "%s/scene/s.json", dir);
    persp_scene *s = NULL;
    assert_int_equal(persp_scene_load(ctx, scene, &s), PERSP_ERR_IO); /* the last, "up/..." */
    persp_context_destroy(ctx);
}

/* A confined read checks the file it opened, not only the name before the
 * open: a link swapped between the two lands on a file whose identity
 * differs from what the name resolves to afterwards, and is refused. A
 * real race cannot be timed in a test; persp__fd_inside is the check the
 * open makes, given a descriptor and a name as they stand after a swap. */
static void test_open_inside_checks_the_file_opened(void **state)
{
    (void)state;
    char root_dir[512], a[600], b[600], outside[512], link[600], missing[600];
    path_in(root_dir, sizeof root_dir, "confined");
    mkdir(root_dir, 0777);
    char *root = realpath(root_dir, NULL);
    assert_non_null(root);
    snprintf(a, sizeof a, "%s/a.txt", root_dir);
    snprintf(b, sizeof b, "%s/b.txt", root_dir);
    snprintf(link, sizeof link, "%s/l.txt", root_dir);
    snprintf(missing, sizeof missing, "%s/none.txt", root_dir);
    path_in(outside, sizeof outside, "outside.txt");
    write_text(a, "a");
    write_text(b, "b");
    write_text(outside, "secret");

    /* An inside file opens; a link to outside and a missing file do not. */
    int fd = persp__open_inside(root, a);
    assert_true(fd >= 0);
    assert_int_equal(persp__fd_inside(fd, root, a), 1);
    /* The name now resolves to another inside file than the one opened. */
    assert_int_equal(persp__fd_inside(fd, root, b), 0);
    close(fd);
    unlink(link);
    assert_int_equal(symlink(outside, link), 0);
    assert_int_equal(persp__open_inside(root, link), PERSP_OPEN_OUTSIDE);
    errno = 0;
    assert_int_equal(persp__open_inside(root, missing), -1);
    assert_int_equal(errno, ENOENT);
    fd = persp__open_inside(NULL, link); /* no root: any file */
    assert_true(fd >= 0);
    close(fd);

    /* The swap: the link pointed outside when it was opened and points
     * inside by the time it is checked. The name alone passes; the file
     * opened does not. */
    fd = open(link, O_RDONLY | O_CLOEXEC);
    assert_true(fd >= 0);
    assert_int_equal(unlink(link), 0);
    assert_int_equal(symlink(a, link), 0);
    assert_int_equal(persp__path_inside(root, link), 1);
    assert_int_equal(persp__fd_inside(fd, root, link), 0);
    close(fd);

    /* Through the readers: the same refusal, as an I/O error saying so. */
    persp_context *ctx = test_context();
    char *data = NULL;
    size_t size = 0;
    assert_int_equal(persp__read_file_inside(ctx, root, a, &data, &size), PERSP_OK);
    assert_int_equal(size, 1);
    assert_int_equal(data[0], 'a');
    persp__free(ctx, data);
    assert_int_equal(unlink(link), 0);
    assert_int_equal(symlink(outside, link), 0);
    assert_int_equal(persp__read_file_inside(ctx, root, link, &data, &size), PERSP_ERR_IO);
    assert_null(data);
    assert_non_null(strstr(persp_context_error(ctx), "is outside the folder"));
    assert_null(strstr(persp_context_error(ctx), "secret"));
    persp_image img;
    assert_int_equal(persp__image_load_inside(ctx, root, link, &img), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "is outside the folder"));
    /* The streaming open of the OBJ reader too. */
    FILE *stream = NULL;
    assert_int_equal(persp__open_stream_inside(ctx, root, link, &stream, &size), PERSP_ERR_IO);
    assert_null(stream);
    assert_non_null(strstr(persp_context_error(ctx), "is outside the folder"));
    assert_int_equal(persp__open_stream_inside(ctx, root, a, &stream, &size), PERSP_OK);
    assert_non_null(stream);
    assert_int_equal(size, 1);
    assert_int_equal(fgetc(stream), 'a');
    fclose(stream);
    persp_context_destroy(ctx);
    free(root);
}

typedef struct warnings {
    char text[4096];
    int count;
} warnings;

static void collect(void *user, const char *message)
{
    warnings *w = user;
    size_t n = strlen(w->text);
    snprintf(w->text + n, sizeof w->text - n, "%s\n", message);
    w->count++;
}

/* A model's material library and textures obey the same rule; the refusal
 * is a warning naming the model and the line, and never shows what the
 * refused file holds. */
static void test_model_reads_only_its_folder(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    warnings w;
    memset(&w, 0, sizeof w);
    persp_context_set_warning_handler(ctx, collect, &w);
    char secret[512], sub[512], obj[600], mtl[600];
    path_in(secret, sizeof secret, "secret.mtl");
    write_text(secret, "root:x:0:0:root:/root:/bin/bash\n");
    path_in(secret, sizeof secret, "secret.png");
    copy_source("scenes/textures/checker.png", secret);
    path_in(sub, sizeof sub, "model");
    mkdir(sub, 0777);
    snprintf(obj, sizeof obj, "%s/a.obj", sub);
    snprintf(mtl, sizeof mtl, "%s/b.mtl", sub);
    write_text(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib ../secret.mtl\nmtllib b.mtl\n"
                    "usemtl x\nf 1 2 3\n");
    write_text(mtl, "newmtl x\nKd 1 1 1\nmap_Kd ../secret.png\n");
    persp_scene *s = NULL;
    assert_int_equal(persp_scene_load(ctx, obj, &s), PERSP_OK);
    persp_scene_destroy(s);
    if (!strstr(w.text, "a.obj:4: cannot read '../secret.mtl' (outside the folder") ||
        !strstr(w.text, "(via b.mtl:3): material 'x': cannot load texture '../secret.png' "
                        "(outside the folder"))
        fail_msg("warnings: %s", w.text);
    assert_null(strstr(w.text, "root:x"));
    persp_context_destroy(ctx);
}

/* ---------------------------------------------------------------- messages */

static void test_messages_escape_foreign_text(void **state)
{
    (void)state;
    char buf[PERSP_QUOTE_BYTES];
    const char *esc = "a\x1b[31mb\\";
    assert_string_equal(persp__quote(esc, strlen(esc), buf, sizeof buf), "a\\x1b[31mb\\\\");
    char longer[200];
    memset(longer, 'z', sizeof longer);
    persp__quote(longer, sizeof longer, buf, sizeof buf);
    assert_true(strlen(buf) < sizeof buf);
    assert_string_equal(buf + strlen(buf) - 3, "...");
    /* Through a loader: a terminal escape in a method name. */
    persp_context *ctx = test_context();
    char scene[512];
    path_in(scene, sizeof scene, "esc.json");
    write_text(scene, "{\"render\": {\"method\": \"\\u001b]0;owned\\u0007\"},\n"
                      " \"objects\": [{\"mesh\": \"plane\"}]}\n");
    persp_scene *s = NULL;
    assert_int_equal(persp_scene_load(ctx, scene, &s), PERSP_ERR_NOT_FOUND);
    const char *e = persp_context_error(ctx);
    for (const char *c = e; *c; c++)
        if ((unsigned char)*c < 0x20) fail_msg("control byte 0x%02x in: %s", *c, e);
    assert_non_null(strstr(e, "\\x1b]0;owned\\x07"));
    persp_context_destroy(ctx);
}

/* ------------------------------------------------------------------ output */

static persp_image small_image(persp_context *ctx)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 4, 4, &img), PERSP_OK);
    memset(img.pixels, 200, img.stride * 4);
    return img;
}

typedef struct temp_log {
    char path[1024];
    int created, done;
} temp_log;

static void on_temp(void *user, const char *path)
{
    temp_log *t = user;
    if (path) {
        snprintf(t->path, sizeof t->path, "%s", path);
        t->created++;
        struct stat sb;
        assert_int_equal(stat(path, &sb), 0); /* it exists when announced */
    } else {
        t->done++;
    }
}

static void test_output_replaces_safely(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    temp_log t;
    memset(&t, 0, sizeof t);
    persp_context_set_temp_file_handler(ctx, on_temp, &t);
    persp_image img = small_image(ctx);
    char path[512], link[512];
    path_in(path, sizeof path, "out.png");
    write_text(path, "old");
    assert_int_equal(chmod(path, 0640), 0);
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_OK);
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    assert_int_equal(sb.st_mode & 07777, 0640); /* the mode survives the rename */
    assert_true(sb.st_size > 3);
    assert_int_equal(t.created, 1);
    assert_int_equal(t.done, 1);
    assert_int_not_equal(access(t.path, F_OK), 0); /* renamed away */
    /* Read-only: refused and untouched, even for root (mode bits). */
    write_text(path, "keep");
    assert_int_equal(chmod(path, 0444), 0);
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "read-only"));
    assert_int_equal(stat(path, &sb), 0);
    assert_int_equal(sb.st_size, 4);
    /* A folder, and a link to nothing, are refused. */
    persp_image_write_desc png = {PERSP_IMAGE_FORMAT_PNG, 0};
    assert_int_equal(persp_image_write(ctx, dir, &img, &png), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "is a directory"));
    path_in(link, sizeof link, "dangling.png");
    assert_int_equal(symlink("nowhere.png", link), 0);
    assert_int_equal(persp_image_write(ctx, link, &img, NULL), PERSP_ERR_IO);
    assert_int_equal(lstat(link, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

/* ----------------------------------------------------------------- parsing */

static void test_method_specs_strict(void **state)
{
    (void)state;
    const char *bad[] = {"subdiv: 16",   "subdiv:+8",       "subdiv:0x10",   "subdiv:",
                         "incremental:k= 4", "incremental:k=+4", "incremental:k=0x4",
                         "midpoint:int,int", "midpoint:edge,edge", "constz:eps=0x1p-3",
                         "constz:eps= 1", "constz:eps=inf", "constz:eps=nan"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        if (persp_method_check(bad[i]) == PERSP_OK) fail_msg("'%s' accepted", bad[i]);
    const char *good[] = {"subdiv:16", "subdiv:4", "incremental:k=4", "incremental:bidir",
                          "midpoint:int", "midpoint:int,edge", "constz:eps=0.5",
                          "constz:eps=1e-3"};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
        if (persp_method_check(good[i]) != PERSP_OK) fail_msg("'%s' refused", good[i]);
    long l;
    double d;
    assert_false(persp__parse_long(" 1", 0, 9, &l));
    assert_false(persp__parse_long("1 ", 0, 9, &l));
    assert_false(persp__parse_double("+1", 0, 9, &d));
    assert_true(persp__parse_double("-0.5e1", -9, 9, &d));
    assert_true(d == -5.0);
}

/* Scene filters name the tap range when it is wrong. */
static void test_filter_taps_message(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char scene[512];
    path_in(scene, sizeof scene, "aniso.json");
    write_text(scene, "{\"render\": {\"filter\": \"aniso:0\"}, \"objects\": [{\"mesh\": \"plane\"}]}");
    persp_scene *s = NULL;
    assert_int_equal(persp_scene_load(ctx, scene, &s), PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(ctx), "aniso taps must be 2..16"));
    persp_context_destroy(ctx);
}

/* jansson's allocation failure is reported as one, not as malformed JSON:
 * also where jansson itself reports it as a syntax error (a string token
 * whose copy it cannot allocate, lex_scan_string). */
static int json_allocs_left;
static void *failing_malloc(size_t n)
{
    if (json_allocs_left-- <= 0) return NULL;
    return malloc(n);
}

/* Loads text as a scene with jansson's allocations after the first allow
 * failing. */
static persp_status load_json_failing(persp_context *ctx, const char *text, int allow)
{
    json_set_alloc_funcs(failing_malloc, free);
    json_allocs_left = allow;
    persp_scene *s = NULL;
    persp_status st = persp__scene_load_memory(ctx, text, strlen(text), "oom.json", NULL, 0, &s);
    json_set_alloc_funcs(malloc, free);
    persp_scene_destroy(s);
    return st;
}

static void test_json_out_of_memory(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    /* Strings as keys and values, one longer than the lexer's first buffer
     * (16 bytes, jansson's STRBUFFER_MIN_SIZE), nested objects and arrays. */
    static const char *const scenes[] = {
        "{\"objects\": [{\"mesh\": \"plane\"}]}",
        "{\"materials\": {\"a_material_named_at_length\": {\"ambient\": [0.5, 0.5, 0.5]}},\n"
        " \"objects\": [{\"mesh\": \"plane\", \"material\": \"a_material_named_at_length\"}]}",
    };
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
        /* Every allocation in turn fails, until the parse needs no more. */
        persp_status st = PERSP_ERR_OUT_OF_MEMORY;
        int failures = 0;
        for (int allow = 0; allow < 200 && st != PERSP_OK; allow++) {
            st = load_json_failing(ctx, scenes[k], allow);
            if (st == PERSP_OK) break;
            const char *e = persp_context_error(ctx);
            if (st != PERSP_ERR_OUT_OF_MEMORY || !strstr(e, "out of memory"))
                fail_msg("scene %zu, allocation %d failing: %s (%s)", k, allow, e,
                         persp_status_string(st));
            failures++;
        }
        assert_int_equal(st, PERSP_OK);
        assert_true(failures >= 10); /* the lexer's buffer, strings, objects, arrays, keys */
    }

    /* A file with a real syntax error: out of memory while the failure
     * comes before the error, the error itself once jansson reaches it. */
    static const char bad[] = "{\"objects\": [{\"mesh\": \"plane\"},\n {\"mesh\": \"plane\"} {}]}";
    int oom = 0, format = 0;
    for (int allow = 0; allow < 200; allow++) {
        persp_status st = load_json_failing(ctx, bad, allow);
        const char *e = persp_context_error(ctx);
        if (st == PERSP_ERR_OUT_OF_MEMORY) {
            assert_true(format == 0); /* no memory failure after the error is reached */
            oom++;
            continue;
        }
        assert_int_equal(st, PERSP_ERR_FORMAT);
        if (!strstr(e, "oom.json:2:") || !strstr(e, "invalid JSON")) fail_msg("%d: %s", allow, e);
        format++;
    }
    assert_true(oom >= 5);
    assert_true(format > 0);
    persp_context_destroy(ctx);
}

/* One allocation of jansson fails and the rest succeed: the lexer drops
 * the byte its token buffer could not grow for (lex_save ignores the
 * failure), and the parse succeeds with a shortened key, string or number.
 * Each such load must still say out of memory, never give a scene with
 * other values or an unrelated error. */
static int json_fail_at;
static void *failing_once_malloc(size_t n)
{
    return json_fail_at-- == 0 ? NULL : malloc(n);
}

static void test_json_dropped_byte(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    /* A dropped digit changes each number's magnitude, a dropped letter
     * the material's name (then an unknown material). */
    static const char text[] =
        "{\"camera\": {\"position\": [1234567890123456789.5, 2, 3], \"target\": [0, 1234567890123456789, 0]},\n"
        " \"materials\": {\"a_material_named_at_great_length_x\": {\"shininess\": 20}},\n"
        " \"objects\": [{\"mesh\": \"plane\", \"material\": \"a_material_named_at_great_length_x\"}]}";
    persp_scene *ref = NULL;
    assert_int_equal(persp__scene_load_memory(ctx, text, strlen(text), "ref.json", NULL, 0, &ref), PERSP_OK);
    int oom = 0, ok = 0;
    for (int at = 0; at < 400 && ok < 3; at++) {
        json_set_alloc_funcs(failing_once_malloc, free);
        json_fail_at = at;
        persp_scene *s = NULL;
        persp_status st = persp__scene_load_memory(ctx, text, strlen(text), "once.json", NULL, 0, &s);
        json_set_alloc_funcs(malloc, free);
        if (st == PERSP_OK) {
            /* all of it: the failing call came after the parse, or none failed */
            assert_true(s->camera.eye.x == ref->camera.eye.x);
            assert_true(s->camera.target.y == ref->camera.target.y);
            ok++;
        } else if (st == PERSP_ERR_OUT_OF_MEMORY) {
            assert_non_null(strstr(persp_context_error(ctx), "out of memory"));
            oom++;
        } else {
            fail_msg("allocation %d failing: %s (%s)", at, persp_context_error(ctx), persp_status_string(st));
        }
        persp_scene_destroy(s);
    }
    assert_true(oom >= 10);
    assert_true(ok > 0);
    persp_scene_destroy(ref);
    persp_context_destroy(ctx);
}

/* Files jansson refuses as syntax errors stay syntax errors: the check that
 * tells them from a failed allocation finds a bad byte no later than
 * jansson stops. */
static void test_json_syntax_errors_stay_format(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    static const char *const bad[] = {
        "",                                  /* nothing */
        "\"objects\"",                       /* not an object or array */
        "{\"a\" \"b\"}",                     /* no colon */
        "{\"a\": 1 \"b\": 2}",               /* no comma */
        "{\"a\": [1,]}",                     /* a comma before ']' */
        "{\"a\": 01}",                       /* a leading zero */
        "{\"a\": 1.}",                       /* no digit after '.' */
        "{\"a\": -}",                        /* no digit after '-' */
        "{\"a\": 1e+}",                      /* no exponent digit */
        "{\"a\": tru}",                      /* a short literal */
        "{\"a\": truex}",                    /* a long one */
        "{\"a\": nul}",
        "{\"a\": \"x\\q\"}",                 /* a bad escape */
        "{\"a\": \"x\\u12\"}",               /* a short \u escape */
        "{\"a\": \"\\udc00\"}",              /* a low surrogate alone */
        "{\"a\": \"\\ud800\"}",              /* a high one alone */
        "{\"a\": \"\\ud800\\u0041\"}",       /* followed by no low one */
        "{\"a\": \"tab\there\"}",            /* a control byte */
        "{\"a\": \"x\"}}",                   /* text after the end */
        "{\"a\": [1, 2}",                    /* the wrong bracket */
        "{\"a\": @}",                        /* a stray byte */
        "{\"a\":",                           /* the end too early */
        "{\"a\": \"open",                    /* a string never closed */
        "{\"a\": \"x\"\"b\": 1}",            /* a string right after a string */
        "{1: 2}",                            /* a number as a key */
        "[\"\\ud83d\\ude00\", \"\\ud83d\"]", /* a pair, then a high one alone */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        persp_scene *s = NULL;
        persp_status st =
            persp__scene_load_memory(ctx, bad[i], strlen(bad[i]), "bad.json", NULL, 0, &s);
        persp_scene_destroy(s);
        const char *e = persp_context_error(ctx);
        if (st != PERSP_ERR_FORMAT || !strstr(e, "invalid JSON"))
            fail_msg("'%s': %s (%s)", bad[i], e, persp_status_string(st));
    }
    /* NUL bytes: after a backslash, and in place of a value. */
    static const char nul_escape[] = "{\"a\": \"x\\\0\"}", nul_value[] = "{\"a\": \0}";
    const char *const nul_texts[] = {nul_escape, nul_value};
    const size_t nul_sizes[] = {sizeof nul_escape - 1, sizeof nul_value - 1};
    for (size_t i = 0; i < 2; i++) {
        persp_scene *sc = NULL;
        persp_status st =
            persp__scene_load_memory(ctx, nul_texts[i], nul_sizes[i], "nul.json", NULL, 0, &sc);
        persp_scene_destroy(sc);
        if (st != PERSP_ERR_FORMAT || !strstr(persp_context_error(ctx), "invalid JSON"))
            fail_msg("NUL text %zu: %s (%s)", i, persp_context_error(ctx), persp_status_string(st));
    }
    /* Valid text with what jansson checks apart from syntax. */
    persp_scene *s = NULL;
    static const char dup[] = "{\"objects\": [], \"objects\": []}";
    assert_int_equal(persp__scene_load_memory(ctx, dup, strlen(dup), "d.json", NULL, 0, &s),
                     PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(ctx), "duplicate"));
    persp_context_destroy(ctx);
}

/* ------------------------------------------------------------------ images */

/* 4x1 paletted PNG, palette of 2 entries, pixels 0, 1, 5, 200. */
static const unsigned char bad_palette_png[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
    0x52, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x01, 0x08, 0x03, 0x00, 0x00, 0x00, 0xce,
    0xe2, 0xff, 0xff, 0x00, 0x00, 0x00, 0x06, 0x50, 0x4c, 0x54, 0x45, 0xff, 0x00, 0x00, 0x00,
    0xff, 0x00, 0xd2, 0x87, 0xef, 0x71, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78,
    0xda, 0x63, 0x60, 0x60, 0x64, 0x3d, 0x01, 0x00, 0x00, 0xda, 0x00, 0xcf, 0x8d, 0xb5, 0x9f,
    0xc2, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

static void test_palette_index_past_palette(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_load_memory(ctx, bad_palette_png, sizeof bad_palette_png,
                                             "pal.png", &img),
                     PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(ctx), "palette index 5"));
    persp_context_destroy(ctx);
}

/* A translucent texture drawn with persp_draw leaves the framebuffer
 * opaque, as persp_render does (test_image_decode). */
static void test_draw_output_opaque(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image texel;
    assert_int_equal(persp_image_alloc(ctx, 2, 2, &texel), PERSP_OK);
    for (int i = 0; i < 4; i++) {
        texel.pixels[4 * i + 0] = 255, texel.pixels[4 * i + 1] = 0;
        texel.pixels[4 * i + 2] = 0, texel.pixels[4 * i + 3] = 64;
    }
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &texel, &tex), PERSP_OK);
    persp_vertex v[3] = {{{-1, -1, 0}, {0, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                         {{3, -1, 0}, {2, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                         {{-1, 3, 0}, {0, 2}, {0, 0, 1}, {1, 1, 1, 1}}};
    uint32_t idx[3] = {0, 1, 2};
    uint8_t color[8 * 8 * 4];
    float depth[8 * 8];
    persp_framebuffer fb = {8, 8, color, depth};
    const uint8_t clear[4] = {0, 0, 0, 255};
    for (int textured = 0; textured < 2; textured++) {
        persp_framebuffer_clear(&fb, clear, PERSP_DEPTH_Z);
        persp_draw_desc d;
        memset(&d, 0, sizeof d);
        d.mvp = persp_mat4_identity();
        d.texture = textured ? tex : NULL;
        assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, idx, 3), PERSP_OK);
        for (int i = 0; i < 64; i++)
            if (color[4 * i + 3] != 255)
                fail_msg("%s: pixel %d alpha %d", textured ? "texture" : "vertex colour", i,
                         color[4 * i + 3]);
        assert_int_equal(color[0], 255); /* red texel, or white vertex colour */
    }
    persp_texture_destroy(tex);
    persp_image_free(ctx, &texel);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_reads_only_its_folder),
        cmocka_unit_test(test_model_reads_only_its_folder),
        cmocka_unit_test(test_open_inside_checks_the_file_opened),
        cmocka_unit_test(test_messages_escape_foreign_text),
        cmocka_unit_test(test_output_replaces_safely),
        cmocka_unit_test(test_method_specs_strict),
        cmocka_unit_test(test_filter_taps_message),
        cmocka_unit_test(test_json_out_of_memory),
        cmocka_unit_test(test_json_dropped_byte),
        cmocka_unit_test(test_json_syntax_errors_stay_format),
        cmocka_unit_test(test_palette_index_past_palette),
        cmocka_unit_test(test_draw_output_opaque),
    };
    return cmocka_run_group_tests(tests, setup_dir, remove_dir);
}
