/*
 * What the pipeline stages hand each other (internal): vertices carried
 * through clipping, set-up triangles and the per-draw state. Types only, so
 * that the rasterizer (src/raster/), the shaders (src/shade/) and the
 * object-space pipeline (src/objspace/) share them without any of them
 * depending on another's implementation.
 */
#ifndef PERSP_PIPELINE_TYPES_H
#define PERSP_PIPELINE_TYPES_H

#include "geom/scene.h"
#include "interp/method.h"
#include "texture/texture.h"

#include <stdint.h>

/* Per-vertex attributes carried through clipping (linear in clip space). */
enum {
    PERSP_A_U, PERSP_A_V,
    PERSP_A_R, PERSP_A_G, PERSP_A_B, PERSP_A_A,
    PERSP_A_NX, PERSP_A_NY, PERSP_A_NZ, /* eye-space normal */
    PERSP_A_EX, PERSP_A_EY, PERSP_A_EZ, /* eye-space position */
    PERSP_A_BR, PERSP_A_BG, PERSP_A_BB, /* Gouraud: the back face's vertex colour */
    PERSP_A_COUNT
};

typedef struct persp_clipvert {
    float clip[4];
    float attr[PERSP_A_COUNT];
} persp_clipvert;

/* Set-up triangle: fixed-point edges, bounding box and the screen-space
 * planes every method reads (Heckbert's a..i in `rat`). */
typedef struct persp_tri {
    /* What every pixel of an unlit span reads comes first, so that it
     * shares the record's first few cache lines (records are read back
     * cold, after the whole batch is set up). */
    int64_t ea[3], eb[3], ec[3]; /* edge k: ea·X + eb·Y + ec >= 0 inside (X, Y in 1/256 px), top-left bias folded into ec */
    int xmin, xmax, ymin, ymax;  /* inclusive pixel bounding box inside the viewport */
    double zp[3];                /* window depth plane: z = zp0·x + zp1·y + zp2 */
    uint32_t state;              /* index of the draw state */
    uint32_t prep;               /* index into the method prep array, or UINT32_MAX */
    float poly_lambda;           /* per-polygon level of detail */
    int backfacing;
    float light_side;            /* two-sided lighting: 1 lights the front, -1 the back
                                    (persp__shade_light_side, at set-up) */
    uint32_t cover;              /* box of at most PERSP_SMALL_BOX_PIXELS, under 32 wide:
                                    bit (y − ymin)·(xmax − xmin + 1) + x − xmin set for
                                    each covered pixel centre (persp__tri_edges); else 0 */
    persp_rational rat;          /* s1 = u, s2 = v */
    persp_rational bary;         /* s1 = b1, s2 = b2 (perspective-correct barycentrics) */
    double lb1[3], lb2[3];       /* screen-linear barycentric planes (classical Gouraud/Phong) */
    float vattr[3][PERSP_A_COUNT]; /* vertex attributes in setup vertex order */
} persp_tri;

/* Lights transformed to eye space once per frame. */
typedef struct persp_eye_light {
    persp_light_type type;
    float pos[3];   /* eye-space position, or unit direction towards the light */
    float color[3];
    float atten[3];
} persp_eye_light;

typedef struct persp_lighting {
    int count;
    persp_eye_light light[PERSP_SCENE_MAX_LIGHTS];
    float ambient[3];
} persp_lighting;

/* Everything a draw needs, resolved once (docs/DESIGN.md, "Choices resolved
 * once per draw"): never a switch per pixel. */
typedef struct persp_draw_state {
    persp_method_sel method;          /* texture coordinates */
    persp_method_sel shade_method;    /* perspective parameter for shading */
    const struct persp_texture *tex;  /* NULL: untextured */
    persp_sampler_state sampler;
    persp_shading shading;
    persp_material material;
    persp_lighting lighting;
    int depth_test, depth_write;
    /* The span shader returns the texel unchanged, so the renderer may
     * sample straight into the destination and light nothing: a texture
     * without lighting, or with the texture environment replace, whose
     * colour is the texel's whatever the lighting ([CS300-TexMap]'s
     * "replace"; GL 1.5 table 3.22; every lit shader ends in combine_soa,
     * which copies the texel for it). */
    int shade_is_texel;
    /* Decided once when the frame takes the state (persp__frame_add_state,
     * frame.c): u, v and the shader's perspective-correct weights from one
     * reciprocal per pixel (shade_batch), and small triangles drawn as rows
     * packed into lanes (draw_small). */
    int fuse_weights, small_lanes;
    /* The mesh's vertex colours multiply the material's ambient and diffuse
     * colours of lit modes (as glColorMaterial(GL_AMBIENT_AND_DIFFUSE)
     * does, and glTF's COLOR_0 the base colour); set only when some vertex
     * colour is not white, so other draws skip the per-pixel products. */
    int color_material;
    int force_opaque; /* set every written alpha to 255 (persp_draw: the caller's texture and
                         vertex colours may carry alpha; scene textures are made opaque at load) */
    int isa; /* PERSP_ISA_* of the lighting loops: the context's (persp__shade_resolve) */
    /* Span shader chosen from shading and texture environment. */
    void (*shade)(const struct persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                  const float *q, const uint32_t *texel, uint32_t *out);
} persp_draw_state;

/* Per-pixel capture of a scene render for analysis (persp accuracy on a
 * built-in scene): for every pixel the index of the triangle visible there
 * (-1: background) and the s1 = u, s2 = v the method produced; rats[i] is
 * the rational form (Heckbert's coefficients, texture coordinates in
 * normalised units) of triangle i. All arrays are allocated with the
 * context's allocator; release with persp__capture_free
 * (src/render/render.h). */
typedef struct persp_capture {
    int width, height;
    int32_t *tri;  /* width*height, row 0 = bottom */
    float *s1, *s2;
    persp_rational *rats;
    persp_rational_vertices *rat_vertices; /* the vertices of rats[i] */
    size_t rat_count;
    persp_opcount ops; /* the method's operations, with desc->count_ops */
} persp_capture;

#endif
