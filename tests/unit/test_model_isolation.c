/* The model importer in its own process (src/model/import_run.c,
 * docs/RELIABILITY.md, "Model files from strangers"): a reader that crashes,
 * allocates without bound or never answers ends with a one-line failure and
 * the program goes on; the budget holds the importer; an importer whose
 * answer breaks the protocol is refused; the formats read by default and
 * the content they must have; files that are not regular; no memory left
 * behind by a failed import, in either mode. */
#include "model_load.h"

#include "io/text.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* Assimp 5.2 leaks inside some of its readers on malformed input when it
 * runs in this process (test_failed_import_leaves_nothing's in-process
 * half); persp's own blocks are counted by the test itself. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libassimp.so\nleak:libstdc++.so\n"; }

static char tmpdir[64];

static void make_tmp(void) { assert_int_equal(test_tmpdir_make(tmpdir, sizeof tmpdir, "isolation"), 0); }
static void remove_tmp(void) { assert_int_equal(test_tmpdir_remove(tmpdir), 0); }

static void tmp_path(char *out, size_t size, const char *name) { snprintf(out, size, "%s/%s", tmpdir, name); }

static void write_file(const char *name, const void *data, size_t size, int executable)
{
    char path[1024];
    tmp_path(path, sizeof path, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
    if (executable) assert_int_equal(chmod(path, 0755), 0);
}

static void write_text(const char *name, const char *text) { write_file(name, text, strlen(text), 0); }

/* A glTF whose node i has node i + 1 as its only child: Assimp 5.2's glTF
 * reader recurses once per level and overflows its stack near 20 000. */
static char *deep_gltf(int levels, size_t *size)
{
    size_t cap = (size_t)levels * 24 + 256, n = 0;
    char *s = malloc(cap);
    assert_non_null(s);
    n += (size_t)snprintf(s + n, cap - n, "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[");
    for (int i = 0; i + 1 < levels; i++) n += (size_t)snprintf(s + n, cap - n, "{\"children\":[%d]},", i + 1);
    n += (size_t)snprintf(s + n, cap - n, "{}]}");
    *size = n;
    return s;
}

/* Counts the bytes persp holds through the context's allocator. */
typedef struct counter {
    long long live;
    long long blocks;
} counter;

static void *count_alloc(void *user, size_t size)
{
    counter *c = user;
    size_t *p = malloc(size + 16);
    if (!p) return NULL;
    p[0] = size;
    c->live += (long long)size;
    c->blocks++;
    return (char *)p + 16;
}

static void count_free(void *user, void *ptr)
{
    if (!ptr) return;
    counter *c = user;
    size_t *p = (size_t *)(void *)((char *)ptr - 16);
    c->live -= (long long)p[0];
    c->blocks--;
    free(p);
}

/* Loads path with desc under a counting allocator and a budget (0: none);
 * returns the status, the detail in detail. Fails the test if the context
 * holds any byte after it is destroyed. */
static persp_status load_counted(const char *path, const persp_scene_load_desc *desc, size_t budget,
                                 char *detail, size_t cap)
{
    counter c = {0, 0};
    persp_allocator a = {count_alloc, count_free, &c};
    persp_context_desc cd = {.allocator = &a, .max_memory = budget};
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
    persp_scene *scene = NULL;
    persp_status st = persp_scene_load_ex(ctx, path, desc, &scene);
    snprintf(detail, cap, "%s", persp_context_error(ctx));
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    if (c.live != 0 || c.blocks != 0)
        fail_msg("%s: %lld bytes in %lld blocks left after persp_context_destroy", path, c.live, c.blocks);
    return st;
}

static int one_line(const char *s) { return s[0] && !strpbrk(s, "\r\n"); }

/* A reader's crash is the importer's end, reported; the caller goes on and
 * the next load works. Through a JSON scene naming the model as well. */
static void test_crash_contained(void **state)
{
    (void)state;
    make_tmp();
    size_t n;
    char *deep = deep_gltf(20000, &n);
    write_file("deep.gltf", deep, n, 0);
    free(deep);
    write_text("scene.json", "{\"objects\": [{\"mesh\": \"deep.gltf\"}]}");
    char path[1024], detail[1024];
    tmp_path(path, sizeof path, "deep.gltf");
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_FORMAT);
    assert_true(one_line(detail));
    assert_non_null(strstr(detail, "deep.gltf: the importer crashed on this file (signal"));
    assert_non_null(strstr(detail, "malformed or hostile"));
    tmp_path(path, sizeof path, "scene.json");
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_FORMAT);
    if (!strstr(detail, "deep.gltf: the importer crashed")) fail_msg("through a scene: '%s'", detail);
    /* the same reader, one level: a model with nothing to draw, refused by the reader's rules */
    deep = deep_gltf(1, &n);
    write_file("flat.gltf", deep, n, 0);
    free(deep);
    tmp_path(path, sizeof path, "flat.gltf");
    persp_status st = load_counted(path, NULL, 0, detail, sizeof detail);
    assert_int_not_equal(st, PERSP_OK);
    assert_null(strstr(detail, "crashed"));
    char model[1024];
    test_source_path(model, sizeof model, "tests/data/models/triangle.dae");
    assert_int_equal(load_counted(model, NULL, 0, detail, sizeof detail), PERSP_OK);
    remove_tmp();
}

/* A mesh declaring a billion vertices in 54 bytes: the importer is held to
 * what the budget leaves and the failure says so, as memory, not as a
 * malformed file. */
static void test_memory_limit_holds(void **state)
{
    (void)state;
    make_tmp();
    write_text("big.x", "xof 0303txt 0032\nMesh m {\n1000000000;\n0.0;0.0;0.0;;\n}\n");
    char path[1024], detail[1024];
    tmp_path(path, sizeof path, "big.x");
    persp_scene_load_desc all = {.formats = PERSP_MODEL_FORMATS_ALL};
    time_t t0 = time(NULL);
    assert_int_equal(load_counted(path, &all, (size_t)96 << 20, detail, sizeof detail), PERSP_ERR_OUT_OF_MEMORY);
    assert_true(time(NULL) - t0 < 10);
    assert_true(one_line(detail));
    assert_non_null(strstr(detail, "big.x: importing the model needs more than the"));
    assert_non_null(strstr(detail, "MiB of memory it may use"));
    /* not a format read by default */
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_UNSUPPORTED);
    assert_non_null(strstr(detail, "big.x: 'x' models are not read by default"));
    remove_tmp();
}

/* Stand-ins for persp-import: one that never answers (the wall-clock limit
 * stops it), ones whose answers break the protocol (refused, not used), one
 * that exits at once. */
static void test_importer_answers_checked(void **state)
{
    (void)state;
    make_tmp();
    char model[1024], path[1024], detail[1024];
    test_source_path(model, sizeof model, "tests/data/models/triangle.dae");
    static const struct {
        const char *script, *expect;
        persp_status st;
    } cases[] = {
        {"#!/bin/sh\nexec sleep 30\n", "the import took longer than its limit of 0.3 s", PERSP_ERR_TOO_LARGE},
        {"#!/bin/sh\nprintf 'Zjunk' >&0\nexec sleep 30\n", "answer is malformed (an unknown record)",
         PERSP_ERR_FORMAT},
        /* a mesh before the header that sizes the tables */
        {"#!/bin/sh\nprintf 'M\\000\\000\\000\\000' >&0\nexec sleep 30\n",
         "answer is malformed (a record before the header)", PERSP_ERR_FORMAT},
        /* a header claiming more meshes than a scene holds */
        {"#!/bin/sh\nprintf 'H\\377\\377\\377\\377\\000\\000\\000\\000\\000\\000\\000\\000' >&0\nexec sleep 30\n",
         "more than", PERSP_ERR_TOO_LARGE},
        {"#!/bin/sh\nexit 0\n", "the model importer ended without an answer", PERSP_ERR_IO},
        {"#!/bin/sh\nkill -SEGV $$\n", "the importer crashed on this file (signal 11", PERSP_ERR_FORMAT},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        write_file("helper.sh", cases[i].script, strlen(cases[i].script), 1);
        tmp_path(path, sizeof path, "helper.sh");
        persp_scene_load_desc d = {.import_helper = path, .import_time_limit_ms = 300};
        time_t t0 = time(NULL);
        persp_status st = load_counted(model, &d, 0, detail, sizeof detail);
        if (st != cases[i].st || !strstr(detail, cases[i].expect) || !one_line(detail))
            fail_msg("case %zu: status %d, detail '%s'", i, (int)st, detail);
        assert_true(time(NULL) - t0 < 5);
    }
    persp_scene_load_desc missing = {.import_helper = "/nonexistent/persp-import"};
    assert_int_equal(load_counted(model, &missing, 0, detail, sizeof detail), PERSP_ERR_UNAVAILABLE);
    assert_non_null(strstr(detail, "cannot find the model importer /nonexistent/persp-import"));
    remove_tmp();
}

/* The formats read by default, each only with the content its name says;
 * a name without a known extension gets the reader its content shows. */
static void test_formats_and_content(void **state)
{
    (void)state;
    make_tmp();
    char glb[1024], path[1024], detail[1024];
    test_source_path(glb, sizeof glb, "tests/data/models/embedded.glb");
    FILE *f = fopen(glb, "rb");
    assert_non_null(f);
    static char bytes[1 << 16];
    size_t n = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    write_file("really-glb.dae", bytes, n, 0);
    write_file("noext", bytes, n, 0);
    tmp_path(path, sizeof path, "really-glb.dae");
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_FORMAT);
    assert_non_null(strstr(detail, "really-glb.dae: the content is not that of a COLLADA file (it looks like "
                                   "binary glTF: rename it .glb)"));
    tmp_path(path, sizeof path, "noext");
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_OK);
    write_text("junk.lwo", "FORM\0\0\0\4LWO2");
    tmp_path(path, sizeof path, "junk.lwo");
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_UNSUPPORTED);
    assert_non_null(strstr(detail, "--formats all enables the rest"));
    remove_tmp();
}

/* A FIFO where a model, its buffer or its material library should be is
 * refused at once, never waited on. */
static void test_special_files_refused(void **state)
{
    (void)state;
    make_tmp();
    char path[1024], detail[1024];
    tmp_path(path, sizeof path, "pipe.gltf");
    assert_int_equal(mkfifo(path, 0600), 0);
    time_t t0 = time(NULL);
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_IO);
    assert_non_null(strstr(detail, "pipe.gltf: is a FIFO (named pipe), not a regular file"));
    tmp_path(path, sizeof path, "buf.bin");
    assert_int_equal(mkfifo(path, 0600), 0);
    char model[1024];
    test_source_path(model, sizeof model, "tests/data/models/embedded.gltf");
    static char text[8192], edited[8192];
    FILE *f = fopen(model, "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *uri = strstr(text, "\"data:application/octet-stream");
    assert_non_null(uri);
    const char *close = strchr(uri + 1, '"');
    snprintf(edited, sizeof edited, "%.*s\"buf.bin\"%s", (int)(uri - text), text, close + 1);
    write_text("fifo-buffer.gltf", edited);
    tmp_path(path, sizeof path, "fifo-buffer.gltf");
    assert_int_equal(load_counted(path, NULL, 0, detail, sizeof detail), PERSP_ERR_IO);
    assert_non_null(strstr(detail, "cannot read 'buf.bin' (a FIFO (named pipe), not a regular file)"));
    assert_true(time(NULL) - t0 < 5);
    remove_tmp();
}

/* A glTF whose buffer declares one byte more than its file: the reader
 * throws with the buffer open. Nothing of the failed import stays with the
 * context, in the helper process or in this one. */
static void test_failed_import_leaves_nothing(void **state)
{
    (void)state;
    make_tmp();
    static const unsigned char bin[36] = {0};
    write_file("b.bin", bin, sizeof bin, 0);
    write_text("short.gltf",
               "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"b.bin\",\"byteLength\":37}],"
               "\"bufferViews\":[{\"buffer\":0,\"byteLength\":37}],"
               "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
               "\"min\":[0,0,0],\"max\":[0,0,0]}],"
               "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
               "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}");
    char path[1024], detail[1024];
    tmp_path(path, sizeof path, "short.gltf");
    const persp_scene_load_desc modes[2] = {{.import = PERSP_MODEL_IMPORT_ISOLATED},
                                            {.import = PERSP_MODEL_IMPORT_IN_PROCESS}};
    for (int m = 0; m < 2; m++) {
        persp_status st = load_counted(path, &modes[m], 0, detail, sizeof detail);
        assert_int_not_equal(st, PERSP_OK);
        assert_true(one_line(detail));
        assert_non_null(strstr(detail, "short.gltf"));
    }
    remove_tmp();
}

static void count_warning(void *user, const char *message)
{
    (void)message;
    ++*(int *)user;
}

/* Readers look for files nobody named (an .md5anim beside an .md5mesh):
 * no warning about them, and a broken model is not blamed on one. */
static void test_unnamed_files_quiet(void **state)
{
    (void)state;
    make_tmp();
    write_text("b.md5mesh", "MD5Version 10\n");
    char path[1024];
    tmp_path(path, sizeof path, "b.md5mesh");
    persp_context *ctx = test_context();
    int warned = 0;
    persp_context_set_warning_handler(ctx, count_warning, &warned);
    persp_scene *scene = NULL;
    persp_scene_load_desc all = {.formats = PERSP_MODEL_FORMATS_ALL};
    assert_int_equal(persp_scene_load_ex(ctx, path, &all, &scene), PERSP_ERR_FORMAT);
    const char *e = persp_context_error(ctx);
    if (strstr(e, "md5anim") || !strstr(e, "b.md5mesh: cannot import the model")) fail_msg("detail '%s'", e);
    assert_int_equal(warned, 0);
    persp_context_destroy(ctx);
    remove_tmp();
}

/* persp-import as persp starts it, looked at from outside before it is
 * sent anything: limits set, no descriptor but the three standard ones,
 * and (outside the sanitizer builds) the address-space limit and the
 * system-call filter in place. */
static void test_helper_confined(void **state)
{
    (void)state;
    char helper[1024];
    test_binary_path(helper, sizeof helper, "persp-import");
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        dup2(sv[1], 0);
        int null = open("/dev/null", O_WRONLY);
        dup2(null, 1), dup2(null, 2);
        /* a descriptor left open by a careless parent: the helper closes it */
        execl(helper, "persp-import", "--memory", "67108864", "--cpu", "5", (char *)NULL);
        _exit(127);
    }
    close(sv[1]);
    char path[64], line[256];
    int seccomp = -1, nnp = -1, tries = 0;
    snprintf(path, sizeof path, "/proc/%d/status", (int)pid);
    /* The limits are set before the first read of the socket: wait until
     * the helper sleeps in that read (State S with its filter, if any). */
    for (; tries < 200; tries++) {
        FILE *f = fopen(path, "r");
        assert_non_null(f);
        int sleeping = 0, named = 0;
        while (fgets(line, sizeof line, f)) {
            if (!strncmp(line, "Name:\tpersp-import", 18)) named = 1;
            if (!strncmp(line, "State:\tS", 8)) sleeping = 1;
            sscanf(line, "Seccomp:\t%d", &seccomp);
            sscanf(line, "NoNewPrivs:\t%d", &nnp);
        }
        fclose(f);
        if (named && sleeping) break;
        const struct timespec ten_ms = {0, 10000000};
        nanosleep(&ten_ms, NULL);
    }
    assert_true(tries < 200);
    snprintf(path, sizeof path, "/proc/%d/limits", (int)pid);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    int core = 0, fsize = 0, nofile = 0, as = 0, cpu = 0;
    while (fgets(line, sizeof line, f)) {
        core += !strncmp(line, "Max core file size", 18) && strstr(line, " 0 ");
        fsize += !strncmp(line, "Max file size", 13) && strstr(line, " 0 ");
        nofile += !strncmp(line, "Max open files", 14) && strstr(line, " 3 ");
        cpu += !strncmp(line, "Max cpu time", 12) && strstr(line, " 5 ");
        as += !strncmp(line, "Max address space", 17) && !strstr(line, "unlimited");
    }
    fclose(f);
    snprintf(path, sizeof path, "/proc/%d/fd", (int)pid);
    int fds = 0;
    DIR *d = opendir(path);
    assert_non_null(d);
    for (struct dirent *e; (e = readdir(d)) != NULL;) fds += e->d_name[0] != '.';
    closedir(d);
    close(sv[0]); /* the helper's read fails: it ends */
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 1);
    assert_int_equal(core + fsize + nofile + cpu, 4);
    assert_int_equal(fds, 3);
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__) && (defined(__x86_64__) || defined(__aarch64__))
    assert_int_equal(as, 1);
    assert_int_equal(seccomp, 2);
    assert_int_equal(nnp, 1);
#else
    (void)as, (void)seccomp, (void)nnp;
#endif
}

/* Both modes build the same scene from the same file. */
static void test_modes_agree(void **state)
{
    (void)state;
    static const char *const models[] = {"tests/data/models/embedded.gltf", "tests/data/models/embedded.glb",
                                         "tests/data/models/triangle.dae", "tests/data/models/triangle.fbx",
                                         "tests/data/models/triangle_binary.stl"};
    for (size_t i = 0; i < sizeof models / sizeof models[0]; i++) {
        char path[1024];
        test_source_path(path, sizeof path, models[i]);
        persp_scene_info info[2];
        uint64_t hash[2];
        for (int m = 0; m < 2; m++) {
            persp_context *ctx = test_context();
            persp_scene *scene = NULL;
            persp_scene_load_desc d = {.import = m ? PERSP_MODEL_IMPORT_IN_PROCESS : PERSP_MODEL_IMPORT_ISOLATED};
            assert_int_equal(persp_scene_load_ex(ctx, path, &d, &scene), PERSP_OK);
            persp_scene_get_info(scene, &info[m]);
            hash[m] = 0;
            for (size_t k = 0; k < scene->mesh_count; k++)
                hash[m] ^= test_hash(scene->meshes[k].vertices, scene->meshes[k].vertex_count * sizeof(persp_vertex)) ^
                           test_hash(scene->meshes[k].indices, scene->meshes[k].index_count * sizeof(uint32_t));
            persp_scene_destroy(scene);
            persp_context_destroy(ctx);
        }
        assert_int_equal(info[0].objects, info[1].objects);
        assert_int_equal(info[0].textures, info[1].textures);
        if (hash[0] != hash[1]) fail_msg("%s: the two modes made different meshes", models[i]);
    }
}

int main(void)
{
    /* No SIGPIPE handling here: a helper that dies while persp writes to
     * it must not end the caller (MSG_NOSIGNAL). */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crash_contained),
        cmocka_unit_test(test_memory_limit_holds),
        cmocka_unit_test(test_importer_answers_checked),
        cmocka_unit_test(test_formats_and_content),
        cmocka_unit_test(test_special_files_refused),
        cmocka_unit_test(test_failed_import_leaves_nothing),
        cmocka_unit_test(test_unnamed_files_quiet),
        cmocka_unit_test(test_helper_confined),
        cmocka_unit_test(test_modes_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
