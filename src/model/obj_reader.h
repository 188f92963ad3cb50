/*
 * The OBJ reader's state (src/model/obj.c), shared with the making of a run's
 * vertices and normals (src/model/obj_vertices.c). Private to those two files.
 */
#ifndef PERSP_IO_OBJ_READER_H
#define PERSP_IO_OBJ_READER_H

#include "model/model.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

/* Longest group, object or material name compared (a run of faces is split
 * where one changes). */
#define OBJ_NAME_MAX 1024
#define NO_INDEX UINT32_MAX
/* Different mtllib statements read (see mtllib). */
#define OBJ_LIBS_MAX 64
/* Bit 31 of a corner's tuple index marks the corner that stands for its
 * polygon corner in the normals (see emit_polygon). */
#define OWNER_BIT 0x80000000u

typedef struct obj_run {
    size_t tris, corners;
    int normals; /* corners with a normal index: 0 none, 1 all, 2 some */
} obj_run;

typedef struct obj_mat {
    size_t name, tex, lib; /* offsets in the name pool; tex NO_NAME: none */
    size_t tex_line;
    size_t glow, glow_line; /* map_Ke: as tex */
    float kd[3], ks[3], ka[3], ke[3], ns;
    int clamp;
    int scene; /* scene material, -1 not made yet */
} obj_mat;

#define NO_NAME SIZE_MAX

typedef struct obj_reader {
    persp_scene *scene;
    persp_context *ctx;
    const char *display, *base_dir, *root, *main_name;
    persp_model *out;
    size_t part_cap;
    persp_model_refs refs;
    size_t max_vertices, vertices_used;
    float crease_deg; /* normals made where the file has none (persp__model_crease) */
    int pass; /* 1: counting, 2: reading */

    /* counted in pass 1 */
    size_t nv, nvt, nvn, max_poly;
    int colours, bad_vn, force_normals;
    obj_run *runs;
    size_t nruns, runs_cap;

    /* attribute arrays (pass 2), filled up to iv, ivt, ivn */
    float *pos, *col, *tc, *nrm;
    size_t iv, ivt, ivn;

    /* group, object and material names: a run ends where one changes */
    char group[OBJ_NAME_MAX], object[OBJ_NAME_MAX], mtl[OBJ_NAME_MAX];
    int has_group, has_object, has_mtl, split;
    size_t run; /* runs seen so far in this pass */

    /* materials */
    obj_mat *mats;
    size_t nmats, mats_cap;
    uint32_t *mat_table; /* hash of the materials' names: index + 1, 0 empty */
    size_t mat_table_cap;
    char *pool;
    size_t pool_len, pool_cap;
    int default_material; /* scene material for faces without one, -1 not yet */
    struct {
        size_t name, len; /* in the name pool */
    } libs[OBJ_LIBS_MAX]; /* mtllib statements read */
    int nlibs;
    const obj_mat *where_mat;
    int where_glow; /* where_mat's map_Ke is being read, not its map_Kd */
    /* faces of fewer than three corners (pass 1): how many, the first's line */
    size_t short_faces, short_line;
    int libs_failed; /* a material library could not be read (warned) */

    /* the run being read (pass 2) */
    int open;         /* a run is being read */
    int run_mat;      /* material record, -1: the default material */
    int file_normals; /* the run keeps the file's normals */
    int run_uv;       /* a face corner of the run names a texture coordinate */
    uint32_t *idx;    /* 3 per triangle: tuple index (| OWNER_BIT) */
    size_t nidx;
    uint32_t *tuples; /* 3 per distinct corner: v, vt, vn (NO_INDEX: none) */
    size_t ntuples, tuples_cap;
    uint32_t *table; /* hash of tuples: index + 1, 0 empty */
    size_t table_cap;
    int area; /* a triangle with area was seen */

    /* scratch for one polygon, max_poly corners */
    uint32_t *poly;   /* tuple index of each corner */
    uint32_t *poly_v; /* position index of each corner */
    int *tri;         /* 3 per triangle of the polygon, corner numbers */
    int *link;        /* ear clipping: next corner, then previous */
    float *flat;      /* ear clipping: 2D corners */
    unsigned char *seen;

    /* generated normals */
    uint32_t *canon;    /* per position: the first position equal to it */
    uint32_t *group_of; /* per canonical position: group in the run, NO_INDEX */
    uint32_t *ctable;   /* hash of the positions read: index + 1, 0 empty */
    size_t ctable_cap;
    uint64_t normals_work; /* their scan steps and corner pairs, all runs (obj_vertices.c) */
    size_t idx_cap; /* entries of idx (from pass 1) */
} obj_reader;

/* Assimp's aiVector3D::NormalizeSafe (quad splitting and normals): a
 * zero vector stays zero. */
static inline void persp__obj_normalize(float *v)
{
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0.0f) {
        float inv = 1.0f / len;
        v[0] *= inv, v[1] *= inv, v[2] *= inv;
    }
}

/* The context's out-of-memory and too-large failures, naming the file. */
persp_status persp__obj_oom(obj_reader *r);
persp_status persp__obj_too_large(obj_reader *r);

/* The table that maps each position read to the first one equal to it
 * (generated normals smooth across them): made before pass 2 when some run
 * needs normals, each position added as it is read. */
persp_status persp__obj_canon_init(obj_reader *r);
void persp__obj_canon_add(obj_reader *r, size_t i);

/* The vertices of the run read so far into mesh (vertices, vertex_count),
 * with the file's normals or normals made as Assimp's GenVertexNormals
 * made them; the latter rewrites r->idx to vertex numbers. */
persp_status persp__obj_run_vertices(obj_reader *r, persp_mesh *mesh);

#endif
