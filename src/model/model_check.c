/*
 * What a model file must satisfy before Assimp reads it: the checks that
 * keep Assimp 5.2's readers from the inputs they crash on or size
 * gigabytes by (declared counts of PLY, OFF and GLB, PLY headers and list
 * counts, glTF's kind and image media types, OBJ library names), each
 * found by the model fuzzer or on real files (docs/RELIABILITY.md).
 */
#include "core/internal.h"
#include "model/model.h"

#include <ctype.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Readers of formats whose header declares element counts (PLY, OFF) size
 * their arrays by the header before reading the data, so a few bytes could
 * ask for gigabytes. Every element takes at least one byte of the file, and
 * vertices are held to persp's own limit, before Assimp sees the file. */

static persp_status check_count(persp_context *ctx, const char *display, const char *what,
                                unsigned long long n, size_t room, unsigned long long limit)
{
    if (n > room || n > limit)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE,
                           "%s: the header declares %llu %s, more than %s holds", display, n, what,
                           n > limit ? "persp" : "the file");
    return PERSP_OK;
}

static const char *next_line(const char *p, const char *end)
{
    while (p < end && *p != '\n')
        p++;
    return p < end ? p + 1 : end;
}

static int printable_line(const char *p, const char *end)
{
    for (; p < end && *p != '\n'; p++)
        if (!((*p >= 0x20 && *p < 0x7f) || *p == '\t' || *p == '\r')) return 0;
    return 1;
}

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Binary glTF declares lengths too: the 12-byte header (magic "glTF",
 * version, total length), then for version 2 chunks of length, type and
 * data (glTF 2.0 specification §4.4, "GLB File Format Specification"), for
 * version 1 a content length and format before the JSON (KHR_binary_glTF).
 * Assimp 5.2 allocates the JSON's declared length before comparing it with
 * the file, so five bytes could ask for 4 GiB: every declared length must
 * fit in the file. */
static persp_status check_glb(persp_context *ctx, const char *display, const unsigned char *b,
                              size_t size)
{
    if (size < 4 || memcmp(b, "glTF", 4) != 0) return PERSP_OK;
    if (size < 12)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: truncated GLB header", display);
    uint32_t version = le32(b + 4), length = le32(b + 8);
    if (length > size)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: truncated GLB: the header declares %u bytes, the file has %zu",
                           display, (unsigned)length, size);
    if (version == 1) {
        if (size < 20 || le32(b + 12) > size - 20)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: truncated GLB: the content is longer than the file", display);
        return PERSP_OK;
    }
    for (size_t pos = 12; size - pos >= 8;) {
        uint32_t len = le32(b + pos);
        if (len > size - pos - 8)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: truncated GLB: the chunk at byte %zu declares %u bytes, %zu "
                               "remain",
                               display, pos, (unsigned)len, size - pos - 8);
        pos += 8 + (size_t)len;
    }
    return PERSP_OK;
}

/* A material library named like a URL ("mtllib abcde://") makes Assimp
 * 5.2's OBJ reader erase a negative length from a string (found by the model
 * fuzzer under ASan); persp resolves material libraries as relative files
 * only, so such a name is refused before Assimp reads the file. Checked
 * whatever the name's extension: Assimp also recognises OBJ by content. */
static persp_status check_obj_mtllib(persp_context *ctx, const char *display, const char *buf,
                                     size_t size)
{
    /* Every "mtllib", not only at line starts: Assimp's OBJ reader also ends
     * a line at a NUL byte. */
    const char *end = buf + size;
    size_t line = 1;
    for (const char *p = buf; p + 7 <= end; p++) {
        if (*p == '\n') line++;
        if (memcmp(p, "mtllib", 6) != 0 || (p[6] != ' ' && p[6] != '\t')) continue;
        for (const char *q = p + 6; q + 3 <= end && *q != '\n' && *q != '\0'; q++)
            if (q[0] == ':' && q[1] == '/' && q[2] == '/')
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                   "%s:%zu: the material library is named like a URL, not a file",
                                   display, line);
    }
    return PERSP_OK;
}

/* A .gltf or .glb file must be binary glTF or a JSON object (glTF 2.0 §3.1,
 * §4.4). Content that is neither is refused by Assimp's glTF reader, and
 * Assimp then offers the file to every reader by content, one of which in
 * Assimp 5.2 reads past the end of its copy of the file (found by the model
 * fuzzer under ASan with "l-geometrynodev "). */
static persp_status check_gltf_kind(persp_context *ctx, const char *display, const char *buf,
                                    size_t size)
{
    if (!persp__model_has_ext(display, "gltf") && !persp__model_has_ext(display, "glb"))
        return PERSP_OK;
    if (size >= 4 && memcmp(buf, "glTF", 4) == 0) return PERSP_OK;
    size_t i = 0;
    while (i < size && isspace((unsigned char)buf[i]))
        i++;
    if (i < size && buf[i] == '{') return PERSP_OK;
    return persp__fail(ctx, PERSP_ERR_FORMAT,
                       "%s: not a glTF file (neither binary glTF nor a JSON object)", display);
}

/* Assimp 5.2's glTF 2 reader takes an embedded image's format from the
 * part of its mimeType after '/' without checking that there is one, and
 * compares from a pointer just past NULL (SIGSEGV, found by the model
 * fuzzer with "image9png"). The mimeType of an image is "image/jpeg" or
 * "image/png" (glTF 2.0 §5.18), so one without '/' is refused. */
/* The JSON of a glTF file: all of a .gltf, the JSON chunk of a binary one
 * (glTF 2.0 §4.4); NULL for other files. */
static const char *gltf_json(const char *display, const char *buf, size_t size, size_t *len)
{
    const unsigned char *b = (const unsigned char *)buf;
    if (size >= 20 && memcmp(b, "glTF", 4) == 0 && le32(b + 4) == 2 &&
        memcmp(b + 16, "JSON", 4) == 0 && le32(b + 12) <= size - 20) {
        *len = le32(b + 12);
        return buf + 20;
    }
    if (persp__model_has_ext(display, "gltf") || persp__model_has_ext(display, "glb")) {
        *len = size;
        return buf;
    }
    return NULL;
}

/* Extensions a glTF may require (glTF 2.0 §3.12, "extensionsRequired")
 * that Assimp 5.2's reader cannot read: it then drops or misreads the
 * attributes (quantized positions came out as a model of zero area), so
 * the file is refused naming the extension. */
static persp_status check_gltf_required(persp_context *ctx, const char *display, const char *buf,
                                        size_t size)
{
    /* The techniques (a draft's GLSL materials, which the glTF sample
     * models use) hold the only texture of their material: drawn without
     * them, the model came out white. */
    static const char *const unread[] = {"KHR_mesh_quantization",   "KHR_draco_mesh_compression",
                                         "EXT_meshopt_compression", "EXT_mesh_gpu_instancing",
                                         "KHR_techniques_webgl",    "KHR_technique_webgl"};
    static const char key[] = "\"extensionsRequired\"";
    size_t len = 0;
    const char *json = gltf_json(display, buf, size, &len);
    for (const char *p = json; p && p + sizeof key - 1 <= json + len; p++) {
        if (memcmp(p, key, sizeof key - 1)) continue;
        const char *close = memchr(p, ']', (size_t)(json + len - p));
        const size_t span = close ? (size_t)(close - p) : (size_t)(json + len - p);
        for (size_t e = 0; e < sizeof unread / sizeof unread[0]; e++) {
            const size_t n = strlen(unread[e]);
            for (size_t i = 0; i + n <= span; i++)
                if (!memcmp(p + i, unread[e], n))
                    return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                                       "%s: the file requires the glTF extension %s, which the glTF "
                                       "reader (Assimp 5.2) does not read",
                                       display, unread[e]);
        }
    }
    return PERSP_OK;
}

static persp_status check_gltf_images(persp_context *ctx, const char *display, const char *buf,
                                      size_t size)
{
    size_t len = 0;
    const char *json = gltf_json(display, buf, size, &len);
    if (!json) return PERSP_OK;
    /* Scanned as text, not parsed: Assimp's JSON reader accepts documents a
     * strict parser refuses. */
    const char *end = json + len;
    size_t index = 0;
    for (const char *p = json; p + 10 <= end; p++) {
        if (memcmp(p, "\"mimeType\"", 10) != 0) continue;
        const char *q = p + 10;
        while (q < end && (isspace((unsigned char)*q) || *q == ':'))
            q++;
        const char *v = q < end && *q == '"' ? q + 1 : NULL;
        const char *close = v ? memchr(v, '"', (size_t)(end - v)) : NULL;
        if (!close || !memchr(v, '/', (size_t)(close - v)))
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: image %zu: the mimeType is not a media type such as image/png",
                               display, index);
        index++;
    }
    /* An embedded image's data URI gives the mimeType the same way
     * (RFC 2397: data:[<mediatype>][;base64],<data>), and Assimp then
     * searches for '/' past the media type into the data: without one
     * anywhere, the same SIGSEGV ("data:image\xd9png;base64,...", found by
     * the model fuzzer). A media type, when present, is type/subtype. */
    for (const char *p = json; p + 6 <= end; p++) {
        if (memcmp(p, "\"data:", 6) != 0) continue;
        const char *m = p + 6, *e = m;
        while (e < end && *e != ';' && *e != ',' && *e != '"')
            e++;
        if (e > m && !memchr(m, '/', (size_t)(e - m)))
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: a data URI's media type is not a type/subtype such as image/png",
                               display);
    }
    return PERSP_OK;
}

/* The body of an ASCII PLY walked as its header lays it out (each element's
 * instances, each property one value or a count and that many values):
 * Assimp 5.2 sizes a list by its count as read, whatever the count's
 * declared type, so a count larger than the values left in the file (a
 * "666666666666666" where a uchar belongs took 15 GB, found by the model
 * fuzzer) is refused here. elements: the header's element lines; body: the
 * end_header line. */
/* The line splitting of Assimp 5.2's ASCII PLY body (IOStreamBuffer's
 * getNextLine): '\r', '\n', '\0' and '\f' all end a line, and a line that
 * starts at one of them is skipped up to and past the next '\n', whatever
 * lies between. Walking the body by '\n' alone lost step with the reader:
 * 350 bytes with a '\f' before "666666629333" took 7.5 GB as a list of
 * 946 698 453 values (the count wraps to 32 bits; found by the model
 * fuzzer). Returns the line's start; *eol its end, where the next call
 * starts. */
static int ply_line_end(char c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; }

static const char *ply_body_line(const char *p, const char *end, const char **eol)
{
    if (p < end && ply_line_end(*p)) {
        while (p < end && *p != '\n')
            p++;
        if (p < end) p++;
    }
    const char *e = p;
    while (e < end && !ply_line_end(*e))
        e++;
    *eol = e;
    return p;
}

static persp_status check_ply_lists(persp_context *ctx, const char *display,
                                    const char *const *elements, int n, const char *body,
                                    const char *end)
{
    /* after end_header and the one line-end byte the header reader takes */
    const char *p = body + 10 < end ? body + 11 : end;
    for (int i = 0; i < n && p < end; i++) {
        /* the element's count, then its properties up to the next element */
        const char *q = elements[i] + 8;
        while (q < end && *q == ' ')
            q++;
        while (q < end && *q != ' ' && *q != '\n')
            q++;
        unsigned long long count = strtoull(q, NULL, 10);
        int list[64], nprops = 0;
        const char *stop = i + 1 < n ? elements[i + 1] : body;
        for (const char *l = next_line(elements[i], end); l < stop && nprops < 64;
             l = next_line(l, end))
            if (!strncmp(l, "property ", 9)) list[nprops++] = !strncmp(l, "property list ", 14);
        /* Assimp reads an ASCII instance from one line (PLY::DOM). */
        for (unsigned long long e = 0; e < count && p < end; e++) {
            const char *eol;
            const char *c = ply_body_line(p, end, &eol);
            p = eol < end ? eol + 1 : end;
            for (int k = 0; k < nprops && c < eol; k++) {
                while (c < eol && isspace((unsigned char)*c))
                    c++;
                const char *t = c;
                while (c < eol && !isspace((unsigned char)*c))
                    c++;
                if (!list[k]) continue;
                unsigned long long values = isdigit((unsigned char)*t) ? strtoull(t, NULL, 10) : 0;
                /* each value takes a character and a separator at least */
                if (values > (unsigned long long)(eol - c + 1) / 2)
                    return persp__fail(ctx, PERSP_ERR_FORMAT,
                                       "%s: a PLY list of element %d declares %llu values, more "
                                       "than its line holds",
                                       display, i + 1, values);
                for (unsigned long long v = 0; v < values && c < eol; v++) {
                    while (c < eol && isspace((unsigned char)*c))
                        c++;
                    while (c < eol && !isspace((unsigned char)*c))
                        c++;
                }
            }
        }
    }
    return PERSP_OK;
}

/* Bytes of a PLY scalar type (the format's names and the sized ones); 0
 * for a name it does not know. */
static size_t ply_type_size(const char *t, const char *e)
{
    static const struct {
        const char *name;
        size_t size;
    } types[] = {{"char", 1},   {"uchar", 1},  {"int8", 1},  {"uint8", 1},   {"short", 2},
                 {"ushort", 2}, {"int16", 2},  {"uint16", 2}, {"int", 4},     {"uint", 4},
                 {"int32", 4},  {"uint32", 4}, {"float", 4}, {"float32", 4}, {"double", 8},
                 {"float64", 8}};
    for (size_t k = 0; k < sizeof types / sizeof types[0]; k++)
        if (strlen(types[k].name) == (size_t)(e - t) && !strncmp(t, types[k].name, (size_t)(e - t)))
            return types[k].size;
    return 0;
}

static const char *ply_token(const char *p, const char *end, const char **stop)
{
    while (p < end && (*p == ' ' || *p == '\t'))
        p++;
    *stop = p;
    while (*stop < end && !isspace((unsigned char)**stop))
        (*stop)++;
    return p;
}

/* The body of a binary PLY walked as its header lays it out: a list count
 * whose values would not fit in the rest of the file is refused, as in
 * check_ply_lists (Assimp 5.2 sizes the list by it first). A type persp
 * does not know, or a file that ends early, is left to Assimp. */
static persp_status check_ply_binary(persp_context *ctx, const char *display,
                                     const char *const *elements, int n, const char *body,
                                     const char *end, int big)
{
    const unsigned char *p = (const unsigned char *)next_line(body, end);
    const unsigned char *e = (const unsigned char *)end;
    for (int i = 0; i < n; i++) {
        const char *q = elements[i] + 8, *t;
        q = ply_token(q, end, &t); /* the name */
        q = ply_token(t, end, &t);
        unsigned long long count = strtoull(q, NULL, 10);
        size_t size[64], item[64], stride = 0;
        int nprops = 0, lists = 0;
        const char *stop = i + 1 < n ? elements[i + 1] : body;
        for (const char *l = next_line(elements[i], end); l < stop && nprops < 64; l = next_line(l, end)) {
            if (strncmp(l, "property ", 9) != 0) continue;
            const char *a = ply_token(l + 9, end, &t);
            item[nprops] = 0;
            if ((size_t)(t - a) == 4 && !strncmp(a, "list", 4)) {
                const char *c = ply_token(t, end, &t), *ce = t;
                const char *v = ply_token(t, end, &t);
                size[nprops] = ply_type_size(c, ce);
                item[nprops] = ply_type_size(v, t);
                if (!item[nprops]) return PERSP_OK;
                lists = 1;
            } else {
                size[nprops] = ply_type_size(a, t);
            }
            if (!size[nprops]) return PERSP_OK;
            stride += size[nprops];
            nprops++;
        }
        if (!lists) {
            if (count > (unsigned long long)(e - p) / (stride ? stride : 1)) return PERSP_OK;
            p += count * stride;
            continue;
        }
        for (unsigned long long k = 0; k < count; k++)
            for (int j = 0; j < nprops; j++) {
                if ((size_t)(e - p) < size[j]) return PERSP_OK;
                if (!item[j]) {
                    p += size[j];
                    continue;
                }
                unsigned long long values = 0;
                for (size_t b = 0; b < size[j]; b++)
                    values |= (unsigned long long)p[big ? b : size[j] - 1 - b]
                              << (8 * (size[j] - 1 - b));
                p += size[j];
                if (values > (unsigned long long)(e - p) / item[j])
                    return persp__fail(ctx, PERSP_ERR_FORMAT,
                                       "%s: a PLY list of element %d declares %llu values, more "
                                       "than the file holds",
                                       display, i + 1, values);
                p += values * item[j];
            }
    }
    return PERSP_OK;
}

/* The PLY header's lines up to end_header (*at, or end when there is
 * none): only its own keywords, and up to 64 element lines into elements
 * (*n). */
static persp_status ply_header_lines(persp_context *ctx, const char *display, const char *buf, const char *end,
                                     const char **elements, int *count, const char **at)
{
    int n = 0;
    const char *p;
    /* Assimp's PLY reader loops without end on some malformed headers:
     * only the header's own keywords, up to end_header, get to it, and
     * lines of plain text before the first element, which it skips like
     * comments (old Blender exports carry one on line 3). Inside an
     * element such a line ends its property list, and the reader then
     * sized arrays by garbage: 300 bytes with "foo" and a hundred
     * digits there took 18 GB (found by the model fuzzer). */
    static const char *const keys[] = {"format", "comment", "obj_info", "element", "property"};
    size_t line = 1;
    for (p = next_line(buf, end); p < end; p = next_line(p, end)) {
        line++;
        if (!strncmp(p, "end_header", 10)) break;
        int known = 0;
        for (size_t k = 0; k < sizeof keys / sizeof keys[0] && !known; k++) {
            size_t kl = strlen(keys[k]);
            known = (size_t)(end - p) > kl && !strncmp(p, keys[k], kl) &&
                    (p[kl] == ' ' || p[kl] == '\t' || p[kl] == '\n' || p[kl] == '\r');
        }
        if (!known && n == 0 && printable_line(p, end)) known = 1;
        if (!known)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s:%zu: expected a PLY header keyword (format, comment, "
                               "obj_info, element, property, end_header)",
                               display, line);
        const char *bad = NULL;
        if (!strncmp(p, "format", 6) && strncmp(p, "format ascii 1.0", 16) != 0 &&
            strncmp(p, "format binary_little_endian 1.0", 31) != 0 &&
            strncmp(p, "format binary_big_endian 1.0", 28) != 0)
            bad = "expected format ascii, binary_little_endian or binary_big_endian 1.0";
        if (!strncmp(p, "property", 8) && n == 0) bad = "a property before any element";
        if (bad) return persp__fail(ctx, PERSP_ERR_FORMAT, "%s:%zu: %s", display, line, bad);
        if (!strncmp(p, "element ", 8) && n < 64) elements[n++] = p;
    }
    *count = n;
    *at = p;
    return PERSP_OK;
}

/* The header's bytes up to end_header at p, and end_header itself on a
 * line of its own after at least one element. */
static persp_status ply_header_end(persp_context *ctx, const char *display, const char *buf, const char *end,
                                   const char *p, int n)
{
    /* Header lines end as '\n' reads them here only when no other byte
     * Assimp's reader takes for a line end (ply_line_end) is among them. */
    for (const char *h = buf; h < p; h++)
        if ((*h == '\r' && h + 1 < p && h[1] != '\n') || *h == '\0' || *h == '\f')
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: the PLY header holds a carriage return, form feed or NUL "
                               "byte inside a line",
                               display);
    const char *after = p + 10;
    if (p >= end || n == 0 ||
        !(after < end &&
          (*after == '\n' || (*after == '\r' && after + 1 < end && after[1] == '\n'))))
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: the PLY header has no element or no end_header line", display);
    return PERSP_OK;
}

/* Each element's name and count: no name of digits, no name twice, no
 * count the rest of the file cannot hold; *vertices: the vertex count. */
static persp_status ply_element_counts(persp_context *ctx, const char *display, const char *end, const char *p,
                                       const char *const *elements, int n, unsigned long long *vertices)
{
    size_t room = (size_t)(end - next_line(p, end));
    *vertices = 0;
    for (int i = 0; i < n; i++) {
        const char *q = elements[i] + 8;
        while (q < end && *q == ' ')
            q++;
        /* Assimp 5.2 reads the count of an element whose name it does
         * not know from where the name starts, so a name of digits
         * would be taken as a count this check never saw. */
        if (q < end && isdigit((unsigned char)*q))
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: PLY element %d: the name starts with a digit", display,
                               i + 1);
        /* A second element of a name: Assimp 5.2's PLY loader sizes
         * the vertex array by the first "vertex" element and writes
         * the instances of every one into it (a heap overflow, found
         * by the model fuzzer; it corrupted the heap unseen until a
         * later import freed). The format gives every element its
         * own name. */
        const char *name_end = q;
        while (name_end < end && *name_end != ' ' && *name_end != '\t' && *name_end != '\n' &&
               *name_end != '\r')
            name_end++;
        for (int k = 0; k < i; k++) {
            const char *o = elements[k] + 8;
            while (o < end && *o == ' ')
                o++;
            const size_t len = (size_t)(name_end - q);
            if ((size_t)(end - o) > len && !strncmp(o, q, len) &&
                (o[len] == ' ' || o[len] == '\t' || o[len] == '\n' || o[len] == '\r'))
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                   "%s: PLY elements %d and %d have the same name '%.*s'",
                                   display, k + 1, i + 1, (int)PERSP_MIN(len, (size_t)40), q);
        }
        int vertex = !strncmp(q, "vertex ", 7);
        while (q < end && *q != ' ' && *q != '\n')
            q++;
        unsigned long long count = strtoull(q, NULL, 10);
        persp_status st =
            check_count(ctx, display, vertex ? "vertices" : "elements", count, room,
                        vertex ? PERSP_SCENE_MAX_VERTICES : (unsigned long long)-1);
        if (st != PERSP_OK) return st;
        if (vertex) *vertices += count;
    }
    return PERSP_OK;
}

/* A PLY file's header, its element counts and lists against the bytes
 * that follow (Assimp 5.2's reader trusts them). */
static persp_status check_ply(persp_context *ctx, const char *display, const char *buf, size_t size)
{
    const char *end = buf + size, *p = NULL;
    if (!(size >= 4 && !memcmp(buf, "ply", 3) &&
          (buf[3] == '\n' || (buf[3] == '\r' && size >= 5 && buf[4] == '\n'))))
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s:1: expected 'ply' alone on the first line", display);
    const char *elements[64];
    int n = 0;
    unsigned long long vertices = 0;
    persp_status st = ply_header_lines(ctx, display, buf, end, elements, &n, &p);
    if (st == PERSP_OK) st = ply_header_end(ctx, display, buf, end, p, n);
    if (st == PERSP_OK) st = ply_element_counts(ctx, display, end, p, elements, n, &vertices);
    if (st != PERSP_OK) return st;
    /* the format line is among the header's lines checked above */
    const char *fmt = NULL;
    for (const char *l = next_line(buf, end); l < p && !fmt; l = next_line(l, end))
        if (!strncmp(l, "format ", 7)) fmt = l + 7;
    persp_status lst = PERSP_OK;
    if (fmt && !strncmp(fmt, "ascii", 5))
        lst = check_ply_lists(ctx, display, elements, n, p, end);
    else if (fmt && !strncmp(fmt, "binary_", 7))
        lst = check_ply_binary(ctx, display, elements, n, p, end, !strncmp(fmt, "binary_big", 10));
    if (lst != PERSP_OK) return lst;
    /* Nothing to draw without vertices, and Assimp 5.2's PLY loader,
     * given faces or colours but no vertex element, sizes an array by
     * a count that has wrapped below zero (34 GB). */
    if (vertices == 0)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the PLY header declares no vertices",
                           display);
    return PERSP_OK;
}

/* An OFF file's counts against the bytes that follow. */
static persp_status check_off(persp_context *ctx, const char *display, const char *buf, size_t size)
{
    const char *end = buf + size, *p;
    /* OFF, COFF, NOFF, STOFF, ...: the counts follow the keyword, after
     * comment lines. The keyword is optional (as the format has it, and
     * Assimp 5.2's reader then takes the counts from the first line), so a
     * .off file without one is held to the same check: "6666666666660 1 0"
     * as its first line took 10 GB (found by the model fuzzer). */
    /* Assimp converts a text file to UTF-8 before its readers see it,
     * dropping a UTF-8 byte-order mark and re-encoding UTF-16 and UTF-32:
     * the counts are read after the mark ("\xef\xbb\xbf777777777777 ..."
     * took 4.6 GB, found by the model fuzzer), and an OFF file in UTF-16 or
     * UTF-32, which this check would have to decode first, is refused. */
    const char *text = buf;
    if (size >= 3 && !memcmp(buf, "\xef\xbb\xbf", 3)) text = buf + 3;
    const int wide = size >= 2 && (!memcmp(buf, "\xff\xfe", 2) || !memcmp(buf, "\xfe\xff", 2) ||
                                   (size >= 4 && !memcmp(buf, "\0\0\xfe\xff", 4)));
    p = text;
    while (p < end && isalpha((unsigned char)*p))
        p++;
    const int keyword = p - text >= 3 && p - text <= 8 && strncmp(p - 3, "OFF", 3) == 0;
    if (!keyword && !persp__model_has_ext(display, "off")) return PERSP_OK;
    if (wide)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: an OFF file in UTF-16 or UTF-32 (persp reads ASCII or UTF-8)",
                           display);
    if (!keyword) p = text;
    unsigned long long counts[2] = {0, 0};
    for (int k = 0; k < 2 && p < end;) {
        while (p < end && isspace((unsigned char)*p))
            p++;
        if (p < end && *p == '#') {
            p = next_line(p, end);
            continue;
        }
        if (p < end && (*p == '-' || *p == '+'))
            return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: an OFF count has a sign", display);
        if (p >= end || !isdigit((unsigned char)*p)) break;
        counts[k++] = strtoull(p, (char **)&p, 10);
    }
    size_t room = (size_t)(end - p);
    persp_status st =
        check_count(ctx, display, "vertices", counts[0], room, PERSP_SCENE_MAX_VERTICES);
    if (st == PERSP_OK)
        st = check_count(ctx, display, "faces", counts[1], room, (unsigned long long)-1);
    return st;
}

persp_status persp__model_check(persp_context *ctx, const char *display, const char *buf,
                                size_t size)
{
    persp_status st = check_gltf_images(ctx, display, buf, size);
    if (st == PERSP_OK) st = check_gltf_required(ctx, display, buf, size);
    if (st != PERSP_OK) return st;
    st = check_gltf_kind(ctx, display, buf, size);
    if (st == PERSP_OK) st = check_obj_mtllib(ctx, display, buf, size);
    if (st == PERSP_OK) st = check_glb(ctx, display, (const unsigned char *)buf, size);
    if (st != PERSP_OK) return st;
    if (persp__model_has_ext(display, "ply") || (size >= 3 && !memcmp(buf, "ply", 3)))
        return check_ply(ctx, display, buf, size);
    return check_off(ctx, display, buf, size);
}
