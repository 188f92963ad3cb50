/*
 * The conversation between persp and its model importer (Assimp), which
 * runs in a helper process (persp-import) or, when the caller asks for it,
 * on a thread of the calling process: the same bytes over a socket either
 * way (docs/RELIABILITY.md, "Model files from strangers").
 *
 * persp sends one request: the model's name and bytes. The importer answers
 * with records; a record that names a file ('F') waits for persp's reply
 * (the file's bytes or a refusal), since the importer opens no file itself.
 * Both ends are the same build, so numbers travel in the machine's own
 * byte order; persp checks every count against its limits before it
 * allocates, and every index and number before it uses them.
 *
 *   request  u32 magic, u32 version, u64 max_vertices, u32 name length,
 *            name, u64 size, bytes
 *   'H'      u32 meshes, materials, embedded textures (of the importer's scene)
 *   'F'      u32 length, name                  -> u8 reply, u64 size, bytes
 *   'X'      u32 index, width, height, char hint[9], bytes (height 0:
 *            width bytes of an encoded image; else width*height*4 RGBA,
 *            bottom row first)
 *   'T'      u32 index, u8 flags, f32 kd[3], ks[3], ka[3], shininess,
 *            u8 texture kind, u32 embedded index, u8 wrap s, wrap t,
 *            u32 length, name, u32 length, file, then the emissive map:
 *            f32 ke[3], u8 texture kind, u32 embedded index, u8 wrap s,
 *            wrap t, u32 length, file
 *   'M'      u32 index, u8 flags, u64 vertices, u64 indices, then
 *            vertices * 12 f32 (position, normal, uv, rgba), indices * u32
 *   'P'      u32 mesh, u32 material (WIRE_NONE: the default), f32 xf[16]
 *            (column-major), u32 length, material name
 *   'E'      u8 kind, u32 length, message      (the import failed; last)
 *   'D'      (the import succeeded; last)
 */
#ifndef PERSP_IO_IMPORT_WIRE_H
#define PERSP_IO_IMPORT_WIRE_H

#include <stddef.h>
#include <stdint.h>

#define WIRE_MAGIC 0x706d6970u /* "pimp" */
#define WIRE_VERSION 2u
#define WIRE_NONE 0xffffffffu

/* Longest name or message a record carries. */
#define WIRE_MAX_TEXT 4096u

enum {
    WIRE_HEADER = 'H',
    WIRE_FILE = 'F',
    WIRE_EMBEDDED = 'X',
    WIRE_MATERIAL = 'T',
    WIRE_MESH = 'M',
    WIRE_PART = 'P',
    WIRE_ERROR = 'E',
    WIRE_DONE = 'D'
};

/* Replies to 'F'. */
enum { WIRE_FILE_OK = 0, WIRE_FILE_MISSING = 1 };

/* 'T' flags and texture kinds. */
#define WIRE_MAT_STAND_IN 1u /* the reader's stand-in: persp's default material */
#define WIRE_MAT_KD 2u
#define WIRE_MAT_KS 4u
#define WIRE_MAT_KA 8u
#define WIRE_MAT_KE 16u    /* an emissive colour */
#define WIRE_MAT_UNLIT 32u /* the shading model is unlit (glTF KHR_materials_unlit, COLLADA <constant>) */
enum { WIRE_TEX_NONE = 0, WIRE_TEX_FILE, WIRE_TEX_EMBEDDED, WIRE_TEX_EMBEDDED_MISSING };
enum { WIRE_WRAP_REPEAT = 0, WIRE_WRAP_CLAMP, WIRE_WRAP_MIRROR, WIRE_WRAP_DECAL };

/* 'M' flags. */
#define WIRE_MESH_NORMALS 1u /* the file gave normals */
#define WIRE_MESH_NO_UV 2u   /* no texture coordinates */

/* 'E' kinds: how persp reports the failure. */
enum {
    WIRE_ERR_IMPORT = 1,   /* the reader refused the file: its message */
    WIRE_ERR_NO_READER,    /* no reader takes the file */
    WIRE_ERR_FORMAT,       /* persp's own check of the imported scene failed */
    WIRE_ERR_TOO_LARGE,    /* over persp's limits */
    WIRE_ERR_OUT_OF_MEMORY /* the importer ran out of memory */
};

/* One end of the socket. deadline_ms: CLOCK_MONOTONIC milliseconds after
 * which reads and writes give up (0: never). failed: 1 the other end
 * closed or an I/O error, 2 the deadline passed. */
typedef struct wire_chan {
    int fd;
    int64_t deadline_ms;
    int failed;
} wire_chan;

int64_t persp__wire_now_ms(void);
/* 1 when all n bytes went (or came); 0 with c->failed set. */
int persp__wire_write(wire_chan *c, const void *p, size_t n);
int persp__wire_read(wire_chan *c, void *p, size_t n);
/* Reads and drops n bytes. */
int persp__wire_skip(wire_chan *c, uint64_t n);

/* The importer's side: reads the request from fd, imports, answers, and
 * returns 0 (answered, success or refusal) or -1 (the socket failed).
 * Everything it allocates (malloc) is freed before it returns, whatever
 * the importer did. out_of_memory (NULL: none) says whether an allocation
 * failed during the import, which the reader may have reported as
 * something else. Runs in persp-import and on persp's own thread for
 * PERSP_MODEL_IMPORT_IN_PROCESS (src/model/import_serve.c). */
int persp__import_serve(int fd, int (*out_of_memory)(void));

#endif
