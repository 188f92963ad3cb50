/*
 * Heat maps of per-pixel error for persp accuracy --heatmap: a logarithmic
 * colour scale over five fixed decades per quantity (the same for every
 * method and filter, so that maps side by side compare), with a legend (colour bar, decade tick labels and a caption naming
 * the quantity: max(|Δu|, |Δv|) in texels for the methods, the error in
 * 8-bit levels for the filters) drawn with a small built-in bitmap font.
 */
#include "analysis/analysis.h"
#include "core/internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* 3×5 glyphs, one row per entry, bit 2 = left column. */
static const struct {
    char c;
    uint8_t rows[5];
} font[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}},
    {'3', {7, 1, 7, 1, 7}}, {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}},
    {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 2, 2, 2}}, {'8', {7, 5, 7, 5, 7}},
    {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'+', {0, 2, 7, 2, 0}}, {'e', {0, 7, 7, 4, 7}}, {' ', {0, 0, 0, 0, 0}},
    {'a', {0, 6, 1, 5, 7}}, {'d', {1, 1, 7, 5, 7}}, {'i', {2, 0, 2, 2, 2}},
    {'l', {6, 2, 2, 2, 7}}, {'m', {0, 6, 7, 5, 5}}, {'n', {0, 0, 6, 5, 5}},
    {'s', {0, 3, 4, 1, 6}}, {'t', {2, 7, 2, 2, 3}}, {'u', {0, 0, 5, 5, 7}},
    {'v', {0, 0, 5, 5, 2}}, {'x', {0, 0, 5, 2, 5}}, {'(', {1, 2, 2, 2, 1}},
    {')', {4, 2, 2, 2, 4}}, {'|', {2, 2, 2, 2, 2}}, {',', {0, 0, 0, 2, 4}},
    {'r', {0, 0, 6, 4, 4}}, {'o', {0, 0, 7, 5, 7}}, {'b', {4, 4, 7, 5, 7}},
};

static const uint8_t *glyph(char c)
{
    for (size_t i = 0; i < sizeof font / sizeof font[0]; i++)
        if (font[i].c == c) return font[i].rows;
    return NULL;
}

static void put(persp_image *img, int x, int ytop, const uint8_t rgb[3])
{
    if (x < 0 || ytop < 0 || x >= img->width || ytop >= img->height) return;
    uint8_t *p = img->pixels + (size_t)(img->height - 1 - ytop) * img->stride + (size_t)x * 4;
    p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
}

int persp__heatmap_text_width(const char *text, int scale)
{
    int n = (int)strlen(text);
    return n ? (4 * n - 1) * scale : 0;
}

void persp__heatmap_text(persp_image *img, int x, int y, int scale, const char *text,
                         const uint8_t rgb[3])
{
    for (; *text; text++, x += 4 * scale) {
        const uint8_t *g = glyph(*text);
        if (!g) continue;
        for (int r = 0; r < 5; r++)
            for (int c = 0; c < 3; c++)
                if (g[r] & (4 >> c))
                    for (int dy = 0; dy < scale; dy++)
                        for (int dx = 0; dx < scale; dx++)
                            put(img, x + c * scale + dx, y + r * scale + dy, rgb);
    }
}

void persp__heatmap_color(double t, uint8_t rgb[3])
{
    /* Perceptually ordered stops close to matplotlib's viridis. */
    static const double stops[5][3] = {
        {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
    if (!(t > 0.0)) t = 0.0;
    if (t > 1.0) t = 1.0;
    double s = t * 4.0;
    int i = (int)s;
    if (i > 3) i = 3;
    double f = s - (double)i;
    for (int k = 0; k < 3; k++)
        rgb[k] = (uint8_t)lround(stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f);
}

#define DECADES 5

static void decade_label(int k, char *buf, size_t size)
{
    if (k >= 0 && k <= 6) {
        snprintf(buf, size, "1");
        for (int j = 0; j < k; j++) strncat(buf, "0", size - strlen(buf) - 1);
    } else if (k < 0 && k >= -3) {
        snprintf(buf, size, "0.");
        for (int j = 0; j < -k - 1; j++) strncat(buf, "0", size - strlen(buf) - 1);
        strncat(buf, "1", size - strlen(buf) - 1);
    } else {
        snprintf(buf, size, "1e%d", k);
    }
}

persp_status persp__heatmap_write(persp_context *ctx, const char *path, const float *err, int w,
                                  int h, const char *caption, int top_decade)
{
    if (!path || !err || !caption || w <= 0 || h <= 0 || w > PERSP_IMAGE_MAX_SIDE ||
        h > PERSP_IMAGE_MAX_SIDE || top_decade < -3 || top_decade > 6)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "heatmap: bad arguments");
    int hi = top_decade, lo = hi - DECADES;

    /* Text at scale 3: glyphs 15 px tall, legible beside 11 px page text. */
    const int ts = 3, bar_h = 12;
    const int legend_h = 8 + bar_h + 4 + 5 * ts + 6 + 5 * ts + 8;
    /* Wide enough for the caption and for the decade labels not to touch,
     * and at least 256 pixels: the map is enlarged to that width. */
    int widest = 0;
    for (int k = lo; k <= hi; k++) {
        char label[16];
        decade_label(k, label, sizeof label);
        int lw = persp__heatmap_text_width(label, ts);
        if (lw > widest) widest = lw;
    }
    /* The end labels centred on the bar's ends, whole. */
    const int margin = widest / 2 + 2 * ts;
    int need = persp__heatmap_text_width(caption, ts) + 2 * margin;
    if (2 * margin + DECADES * (widest + 4 * ts) > need)
        need = 2 * margin + DECADES * (widest + 4 * ts);
    if (need < 256) need = 256;
    int fx = (need + w - 1) / w, fy = fx;
    if (h * fy < 48) fy = (48 + h - 1) / h;
    if (fx > 64) fx = 64;
    if (fy > 64) fy = 64;
    int iw = w * fx, ih = h * fy + legend_h;
    if (iw < need) iw = need;
    if (iw > PERSP_IMAGE_MAX_SIDE || ih > PERSP_IMAGE_MAX_SIDE)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "heatmap: %dx%d is too large", iw, ih);
    persp_image img;
    persp_status st = persp_image_alloc(ctx, iw, ih, &img);
    if (st != PERSP_OK) return st;
    const uint8_t uncovered[3] = {48, 48, 48}, white[3] = {255, 255, 255};
    for (int y = 0; y < ih; y++)
        for (int x = 0; x < iw; x++) put(&img, x, y, (const uint8_t[3]){0, 0, 0});

    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float e = err[(size_t)y * (size_t)w + (size_t)x];
            uint8_t rgb[3];
            if (e != e) {
                memcpy(rgb, uncovered, 3);
            } else {
                double t = e > 0.0f ? (log10((double)e) - lo) / (double)(hi - lo) : 0.0;
                persp__heatmap_color(t, rgb);
            }
            /* Grid row 0 is the bottom row: it goes to the bottom of the map. */
            int ytop = (h - 1 - y) * fy;
            for (int dy = 0; dy < fy; dy++)
                for (int dx = 0; dx < fx; dx++) put(&img, x * fx + dx, ytop + dy, rgb);
        }

    int by = h * fy + 8, bx0 = margin, bx1 = iw - margin - 1;
    for (int x = bx0; x <= bx1; x++) {
        uint8_t rgb[3];
        persp__heatmap_color((double)(x - bx0) / (double)(bx1 - bx0), rgb);
        for (int dy = 0; dy < bar_h; dy++) put(&img, x, by + dy, rgb);
    }
    for (int k = lo; k <= hi; k++) {
        int x = bx0 + (int)lround((double)(k - lo) / (double)(hi - lo) * (double)(bx1 - bx0));
        for (int dy = 0; dy < 3; dy++) put(&img, x, by + bar_h + dy, white);
        char label[16];
        decade_label(k, label, sizeof label);
        int tw = persp__heatmap_text_width(label, ts);
        int tx = x - tw / 2;
        if (tx < 1) tx = 1;
        if (tx + tw > iw - 1) tx = iw - 1 - tw;
        persp__heatmap_text(&img, tx, by + bar_h + 4, ts, label, white);
    }
    int cw = persp__heatmap_text_width(caption, ts);
    persp__heatmap_text(&img, (iw - cw) / 2, by + bar_h + 4 + 5 * ts + 6, ts, caption, white);
    st = persp_image_write_png(ctx, path, &img);
    persp_image_free(ctx, &img);
    return st;
}
