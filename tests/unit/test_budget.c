/* The memory budget (persp_context_desc.max_memory): requests over it are
 * refused before the allocator is asked, with PERSP_ERR_OUT_OF_MEMORY and a
 * detail naming what and how much; the decoders' and the JSON parser's
 * working memory is reserved before they start; and what persp holds for a
 * model grows with the model, not more. */
#include "support.h"

#include "core/internal.h"
#include "interp/method.h"
#include "raster/frame.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static persp_context *budget_context(test_tracker *t, persp_allocator *al, size_t max_memory)
{
    *al = test_tracker_allocator(t);
    persp_context_desc cd = {.allocator = al, .threads = 1, .max_memory = max_memory};
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
    return ctx;
}

static void assert_detail(persp_context *ctx, const char *a, const char *b)
{
    const char *e = persp_context_error(ctx);
    if (!strstr(e, a) || (b && !strstr(e, b))) fail_msg("detail '%s' lacks '%s' / '%s'", e, a, b ? b : "");
}

static void write_file(const char *path, const void *data, size_t n) { test_write_file(NULL, path, data, n); }

static unsigned char *read_all(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    assert_true(len > 0);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)len);
    assert_non_null(b);
    assert_int_equal(fread(b, 1, (size_t)len, f), (size_t)len);
    fclose(f);
    *n = (size_t)len;
    return b;
}

/* An image and a texture's mip chain whose sizes exceed the budget are
 * refused before the allocator is called at all. */
static void test_refused_before_allocating(void **state)
{
    (void)state;
    test_tracker t;
    persp_allocator al;
    persp_context *ctx = budget_context(&t, &al, (size_t)6 << 20);
    long calls = t.calls;
    persp_image big;
    assert_int_equal(persp_image_alloc(ctx, 2048, 2048, &big), PERSP_ERR_OUT_OF_MEMORY);
    assert_int_equal(t.calls, calls);
    assert_detail(ctx, "2048x2048", "over the memory budget of 6.0 MiB");

    /* 4 MiB of image fit; its texture (4 MiB more, and a third for the mip
     * chain) does not. */
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 1024, 1024, &img), PERSP_OK);
    calls = t.calls;
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &tex), PERSP_ERR_OUT_OF_MEMORY);
    assert_null(tex);
    assert_detail(ctx, "texture", "over the memory budget");
    assert_true(t.calls - calls <= 1); /* at most the texture's small header */
    assert_true(t.peak <= ((size_t)6 << 20));
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
    assert_int_equal(t.live, 0);
}

/* A built-in scene over the budget: refused, nothing held past the budget
 * at any time, everything released. */
static void test_scene_over_budget(void **state)
{
    (void)state;
    test_tracker t;
    persp_allocator al;
    persp_context *ctx = budget_context(&t, &al, (size_t)192 << 10);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_ERR_OUT_OF_MEMORY);
    assert_null(scene);
    assert_detail(ctx, "over the memory budget of 192.0 KiB", NULL);
    assert_true(t.peak <= ((size_t)192 << 10));
    persp_context_destroy(ctx);
    assert_int_equal(t.live, 0);

    /* The same scene with room for it renders. */
    ctx = budget_context(&t, &al, (size_t)8 << 20);
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
    persp_image color, depth;
    assert_int_equal(persp_image_alloc(ctx, 320, 240, &color), PERSP_OK);
    assert_int_equal(persp_image_alloc(ctx, 320, 240, &depth), PERSP_OK);
    persp_framebuffer fb = {320, 240, color.pixels, (float *)(void *)depth.pixels};
    assert_int_equal(persp_render(ctx, scene, NULL, &fb, NULL), PERSP_OK);
    assert_true(t.peak <= ((size_t)8 << 20));
    persp_image_free(ctx, &depth);
    persp_image_free(ctx, &color);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* A scene file's JSON is bounded before jansson parses it: 30 000 empty
 * objects (90 KB of text) would take jansson about 7 MB. */
static void test_json_over_budget(void **state)
{
    (void)state;
    char dir[256], path[300];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "budget"), 0);
    snprintf(path, sizeof path, "%s/many.json", dir);
    size_t n = 30000, len = 0;
    char *text = malloc(3 * n + 64);
    assert_non_null(text);
    len += (size_t)sprintf(text, "{\"comment\": [");
    for (size_t i = 0; i < n; i++) len += (size_t)sprintf(text + len, i ? ",{}" : "{}");
    len += (size_t)sprintf(text + len, "]}\n");
    write_file(path, text, len);
    free(text);

    test_tracker t;
    persp_allocator al;
    persp_context *ctx = budget_context(&t, &al, (size_t)4 << 20);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_ERR_OUT_OF_MEMORY);
    assert_detail(ctx, "many.json: parsing the JSON: needs", "over the memory budget of 4.0 MiB");
    persp_context_destroy(ctx);
    assert_int_equal(t.live, 0);

    /* With room for the parse it is the scene that is wrong, not the memory. */
    ctx = budget_context(&t, &al, (size_t)64 << 20);
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_ERR_FORMAT);
    persp_context_destroy(ctx);
    test_tmpdir_remove(dir);
}

/* Decoders: a PNG whose pixels do not fit, and a progressive JPEG of 640
 * bytes claiming 16384x4096 (libjpeg would keep 2 bytes per coefficient of
 * the whole image), are refused before decoding. */
static void test_decoders_over_budget(void **state)
{
    (void)state;
    char dir[256], png[300], jpg[300];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "budget"), 0);
    snprintf(png, sizeof png, "%s/a.png", dir);
    snprintf(jpg, sizeof jpg, "%s/a.jpg", dir);
    persp_context *plain = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(plain, 512, 512, &img), PERSP_OK);
    for (size_t i = 0; i < (size_t)512 * 512 * 4; i++) img.pixels[i] = (uint8_t)(i * 7 >> 3);
    assert_int_equal(persp_image_write_png(plain, png, &img), PERSP_OK);
    persp_image_free(plain, &img);
    assert_int_equal(persp_image_alloc(plain, 16, 16, &img), PERSP_OK);
    memset(img.pixels, 90, (size_t)16 * 16 * 4);
    assert_int_equal(persp_image_write_jpeg(plain, jpg, &img, 90), PERSP_OK);
    persp_image_free(plain, &img);
    persp_context_destroy(plain);

    test_tracker t;
    persp_allocator al;
    persp_context *ctx = budget_context(&t, &al, (size_t)512 << 10);
    persp_image out;
    assert_int_equal(persp_image_load(ctx, png, &out), PERSP_ERR_OUT_OF_MEMORY);
    assert_detail(ctx, "over the memory budget of 512.0 KiB", NULL);
    assert_true(t.peak <= ((size_t)512 << 10));
    persp_context_destroy(ctx);
    ctx = budget_context(&t, &al, (size_t)2 << 20);
    assert_int_equal(persp_image_load(ctx, png, &out), PERSP_OK);
    persp_image_free(ctx, &out);
    persp_context_destroy(ctx);

    /* The baseline JPEG turned progressive (SOF0 -> SOF2) and 16384x4096:
     * jpeg_read_header accepts it; the budget stops it before
     * jpeg_start_decompress would allocate. */
    size_t n;
    unsigned char *b = read_all(jpg, &n);
    size_t sof = 0;
    for (size_t i = 2; i + 9 < n; i++)
        if (b[i] == 0xff && b[i + 1] == 0xc0) {
            sof = i;
            break;
        }
    assert_true(sof > 0);
    b[sof + 1] = 0xc2;
    b[sof + 5] = 0x10, b[sof + 6] = 0x00; /* height 4096 */
    b[sof + 7] = 0x40, b[sof + 8] = 0x00; /* width 16384 */
    ctx = budget_context(&t, &al, (size_t)64 << 20);
    assert_int_equal(persp_image_load_memory(ctx, b, n, "claim.jpg", &out), PERSP_ERR_OUT_OF_MEMORY);
    assert_detail(ctx, "claim.jpg: decoding the 16384x4096 JPEG: needs", "over the memory budget");
    assert_true(t.peak <= ((size_t)64 << 20));
    persp_context_destroy(ctx);
    assert_int_equal(t.live, 0);
    free(b);

    /* The small JPEG itself decodes within a small budget. */
    ctx = budget_context(&t, &al, (size_t)1 << 20);
    assert_int_equal(persp_image_load(ctx, jpg, &out), PERSP_OK);
    persp_image_free(ctx, &out);
    persp_context_destroy(ctx);
    test_tmpdir_remove(dir);
}

/* What persp holds to load and render a grid model is proportional to the
 * model: at most three times its vertex and index arrays, plus the two
 * framebuffers and a batch of triangle records. The file's text is not
 * held (the OBJ reader streams it in chunks): the bound leaves it out, and
 * fails when the file is read whole (2.3 MB here). */
static void test_grid_memory_proportional(void **state)
{
    (void)state;
    char dir[256], path[300];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "budget"), 0);
    snprintf(path, sizeof path, "%s/grid.obj", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    const int cols = 100, rows = 200;
    for (int j = 0; j <= rows; j++)
        for (int i = 0; i <= cols; i++)
            fprintf(f, "v %.6f %.6f 0\n", 2.0 * i / cols - 1.0, 2.0 * j / rows - 1.0);
    for (int j = 0; j <= rows; j++)
        for (int i = 0; i <= cols; i++) fprintf(f, "vt %.6f %.6f\n", (double)i / cols, (double)j / rows);
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++) {
            int p = j * (cols + 1) + i + 1, q = p + 1, r = p + cols + 2, s = p + cols + 1;
            fprintf(f, "f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n", p, p, q, q, r, r, p, p, r, r, s, s);
        }
    long file_bytes = ftell(f);
    assert_int_equal(fclose(f), 0);

    test_tracker t;
    persp_allocator al;
    persp_context *ctx = budget_context(&t, &al, 0);
    /* Triangle records are held per batch (a fixed amount, src/raster/frame.c);
     * a small batch leaves what grows with the model to be measured. */
    const size_t batch = 1024;
    ctx->frame_batch = batch;
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    size_t load_peak = t.peak, loaded = t.live;
    size_t data = 0, vertices = 0;
    for (size_t i = 0; i < persp_scene_object_count(scene); i++) {
        persp_scene_object o;
        assert_int_equal(persp_scene_get_object(scene, i, &o), PERSP_OK);
        data += o.vertex_count * sizeof(persp_vertex) + o.index_count * sizeof(uint32_t);
        vertices += o.vertex_count;
    }
    /* The six corners of each quad share the grid's vertices again once
     * identical vertices are joined. */
    assert_int_equal(vertices, (size_t)(cols + 1) * (rows + 1));
    const int w = 256, h = 192;
    persp_image color, depth;
    assert_int_equal(persp_image_alloc(ctx, w, h, &color), PERSP_OK);
    assert_int_equal(persp_image_alloc(ctx, w, h, &depth), PERSP_OK);
    persp_framebuffer fb = {w, h, color.pixels, (float *)(void *)depth.pixels};
    persp_render_stats st;
    assert_int_equal(persp_render(ctx, scene, NULL, &fb, &st), PERSP_OK);
    assert_int_equal(st.triangles_in, (uint64_t)cols * rows * 2);
    size_t frame = 2 * ((size_t)w * h * 4 + 128);
    size_t records = 2 * batch * (sizeof(persp_tri) + sizeof(persp_method_prep));
    /* Fixed costs that do not grow with the model: the context, the scene's
     * tables, materials and lights. */
    const size_t fixed = 64 * 1024;
    size_t bound = 3 * data + frame + records + fixed;
    /* Loading alone (the reader's arrays, its 1 MiB window, the mesh) stays
     * within three times the mesh: the 2.3 MB file read whole would not. */
    assert_true(load_peak <= 3 * data);
    print_message("grid %dx%d: vertex and index data %zu, file %ld; loaded %zu, load peak %zu, "
                  "peak %zu bytes (bound %zu)\n",
                  cols, rows, data, file_bytes, loaded, load_peak, t.peak, bound);
    assert_true(t.peak <= bound);
    persp_image_free(ctx, &depth);
    persp_image_free(ctx, &color);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    test_tmpdir_remove(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refused_before_allocating),
        cmocka_unit_test(test_scene_over_budget),
        cmocka_unit_test(test_json_over_budget),
        cmocka_unit_test(test_decoders_over_budget),
        cmocka_unit_test(test_grid_memory_proportional),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
