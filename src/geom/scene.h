/*
 * In-memory scene (internal): what built-in scenes and the JSON loader
 * produce and what persp_render consumes. Every array is owned by the scene
 * and freed by persp_scene_destroy (src/geom/scene.c).
 */
#ifndef PERSP_GEOM_SCENE_H
#define PERSP_GEOM_SCENE_H

#include "core/shared.h"

#include "persp.h"

/* Limits checked before allocating (absurd counts are refused). */
#define PERSP_SCENE_MAX_VERTICES (16u * 1024u * 1024u)
#define PERSP_SCENE_MAX_INDICES (48u * 1024u * 1024u)
#define PERSP_SCENE_MAX_OBJECTS 65536
#define PERSP_SCENE_MAX_LIGHTS 8
#define PERSP_SCENE_MAX_TEXTURES 1024

/* A run of PERSP_CLUSTER_TRIANGLES consecutive triangles of a mesh (the
 * last may be shorter), described so that a frame can decide whether every
 * one of them is a back face it would cull without looking at any of them
 * (src/raster/cluster_cull.c), in object space: a sphere around their
 * vertices, a cone around their face normals (from the winding), their
 * shape, and the vertices they use. Built once, when the mesh joins a
 * scene (src/geom/cluster_build.c); a scene's meshes do not change after. */
#define PERSP_CLUSTER_TRIANGLES 64
#define PERSP_CLUSTER_RUNS 4
typedef struct persp_cluster {
    double center[3], radius;  /* every vertex is within radius of center */
    double half[3];            /* and within half[i] of center along axis i */
    double axis[3];            /* unit; every unit face normal n has n·axis >= cos_a */
    double cos_a, sin_a;       /* the cone's half-angle, cos_a > 0 */
    double alt_min;            /* least height of a triangle over its longest edge, > 0 */
    double edge_min;           /* least longest edge of a triangle, > 0 */
    uint32_t run[PERSP_CLUSTER_RUNS][2]; /* vertex index ranges [first, last + 1) that
                                            hold every vertex the triangles use */
    int runs; /* 0: an index is out of range (the frame refuses the mesh) */
    int usable; /* 0: a degenerate or non-finite triangle, an index out of
                   range, or normals too spread for a cone: never culled whole */
} persp_cluster;

typedef struct persp_mesh {
    persp_vertex *vertices;
    uint32_t *indices; /* triangles, 3 per face, counter-clockwise = front */
    size_t vertex_count, index_count;
    int has_normals;   /* 0: normals were computed by persp */
    int colored;       /* some vertex colour is not white (persp__scene_add_mesh) */
    int no_uv;         /* the model file gave no texture coordinates (persp__object_texture) */
    persp_cluster *clusters; /* index_count / 3 / PERSP_CLUSTER_TRIANGLES rounded up, or NULL */
    size_t cluster_count;
} persp_mesh;

/* Fills mesh->clusters (none for a mesh of fewer than two clusters). */
persp_status persp__mesh_build_clusters(persp_context *ctx, persp_mesh *mesh);

typedef enum persp_texenv {
    PERSP_TEXENV_REPLACE = 0, /* fragment colour = texture colour ([CS300-TexMap]) */
    PERSP_TEXENV_MODULATE     /* fragment colour = lit colour × texture colour */
} persp_texenv;

typedef enum persp_texgen {
    PERSP_TEXGEN_UV = 0,      /* the mesh's own coordinates */
    PERSP_TEXGEN_PLANAR,      /* object-linear: u = P_s·p, v = P_t·p */
    PERSP_TEXGEN_CYLINDRICAL, /* u = angle about the axis, v = height */
    PERSP_TEXGEN_SPHERICAL,   /* u = longitude, v = latitude */
    PERSP_TEXGEN_CUBE,        /* dominant-axis projection */
    PERSP_TEXGEN_REFLECTION   /* sphere map of the eye-space reflection vector */
} persp_texgen;

typedef struct persp_material {
    float ambient[3], diffuse[3], specular[3];
    float shininess;
    int texture;          /* index into scene->textures, -1: none */
    int specular_texture; /* index or -1: texture also modulates specular */
    persp_texenv env;
    persp_sampler_desc sampler;
    /* Light the surface gives off itself, added to the lit colour before a
     * modulating texel multiplies it (OpenGL 1.5 §2.14.1, "e_cm"): a
     * constant of the draw, folded into its ambient term (shade.c). */
    float emission[3];
    /* 1: drawn without lighting, as vertex colour × diffuse × texel (glTF
     * KHR_materials_unlit; scene_render.c draws it with shading none). */
    int unlit;
} persp_material;

typedef struct persp_object {
    int mesh;       /* index into scene->meshes */
    int material;   /* index into scene->materials */
    persp_mat4 model;
    persp_texgen texgen;
    float texgen_s[4], texgen_t[4]; /* planes for PERSP_TEXGEN_PLANAR (object space) */
    float texgen_scale[2];          /* repeats in u, v for generated coordinates (0: 1) */
    int texgen_axis;                /* cylindrical/spherical axis: 0 x, 1 y, 2 z */
    float texgen_center[3];         /* origin of cylindrical/spherical/cube (object space) */
} persp_object;

typedef enum persp_light_type { PERSP_LIGHT_DIRECTIONAL = 0, PERSP_LIGHT_POINT } persp_light_type;

typedef struct persp_light {
    persp_light_type type;
    float position[3];  /* world space; direction *towards* the light when directional */
    float color[3];
    float attenuation[3]; /* constant, linear, quadratic (point lights) */
} persp_light;

typedef struct persp_camera {
    int use_matrix;       /* 1: projection/view given directly (built-in benchmarks) */
    persp_mat4 projection, view;
    persp_vec3 eye, target, up;
    float fovy_deg, znear, zfar;
    /* 1: fovy_deg is the view of the image's shorter side, so that what it
     * frames (a model's bounding sphere) stays whole in a portrait image
     * too; 0: of its height, as gluPerspective's. */
    int fov_shorter_side;
} persp_camera;

struct persp_scene {
    persp_context *ctx;
    persp_camera camera;
    int width, height;        /* preferred image size, 0 if none */
    uint8_t clear[4];
    float ambient[3];         /* global ambient light */
    persp_shading shading;    /* default shading */
    int cull_backfaces;
    char method[64];          /* texture-coordinate method spec from the scene file, "" if none */
    persp_filter filter;      /* the scene file's default texture filter, or DEFAULT */
    int max_aniso;
    persp_mesh *meshes;
    size_t mesh_count, mesh_cap;
    persp_material *materials;
    size_t material_count, material_cap;
    persp_texture **textures;
    size_t texture_count, texture_cap;
    persp_object *objects;
    size_t object_count, object_cap;
    persp_light lights[PERSP_SCENE_MAX_LIGHTS];
    size_t light_count;
    /* While a file loads: the folder its references must stay in (the real
     * path of the loaded file's folder), NULL when any file may be read
     * (persp_scene_load_desc). Not used after the load. */
    const char *load_root;
    /* While a file loads: how models are imported (NULL: the defaults). */
    const persp_scene_load_desc *load_desc;
    /* While a file loads: the wall-clock time its isolated model imports
     * have taken together, and the limit they share, with what their files
     * granted (0: no import yet; src/model/model.c). */
    int64_t import_used_ms;
    unsigned import_limit_ms;
};

/* Allocates an empty scene with defaults (camera at origin looking down -z). */
PERSP_INTERNAL persp_status persp__scene_new(persp_context *ctx, persp_scene **out);
/* Appends (the scene takes ownership; on failure the item is freed). */
PERSP_INTERNAL persp_status persp__scene_add_mesh(persp_scene *s, persp_mesh *mesh, int *index);
/* The texture object o is drawn with: its material's, or -1 where the
 * material has none or would read it through coordinates its mesh does not
 * have (a model file without them, texgen "uv"): every vertex would then
 * fetch the texel at (0, 0), one colour over the whole surface. */
int persp__object_texture(const persp_scene *s, const persp_object *o);
PERSP_INTERNAL persp_status persp__scene_add_texture(persp_scene *s, persp_texture *tex,
                                                     int *index);
PERSP_INTERNAL persp_status persp__scene_add_material(persp_scene *s, const persp_material *m,
                                                      int *index);
PERSP_INTERNAL persp_status persp__scene_add_object(persp_scene *s, const persp_object *o);
PERSP_INTERNAL void persp__mesh_free(persp_context *ctx, persp_mesh *mesh);
/* Normals for a mesh whose file gives none, split at a crease
 * (src/geom/normals.c): corners whose angle-weighted normals differ become
 * vertices of their own. crease_deg 0: flat (only coplanar neighbours
 * smoothed). PERSP_ERR_TOO_LARGE when the split vertices would exceed
 * max_vertices or the scene's limit; PERSP_ERR_OUT_OF_MEMORY; the mesh is
 * unchanged on failure. Sets no error detail. */
persp_status persp__mesh_crease_normals(persp_context *ctx, persp_mesh *m, float crease_deg,
                                        size_t max_vertices);
/* Fills in smooth vertex normals from face normals (area-weighted). */
PERSP_INTERNAL void persp__mesh_compute_normals(persp_mesh *mesh);
/* A default material: white, no texture, replace. */
PERSP_INTERNAL persp_material persp__material_default(void);

/* Built-in meshes (src/geom/primitives.c). */
PERSP_INTERNAL persp_status persp__mesh_plane(persp_context *ctx, int subdiv, persp_mesh *out);
persp_status persp__mesh_cube(persp_context *ctx, persp_mesh *out);
PERSP_INTERNAL persp_status persp__mesh_sphere(persp_context *ctx, int slices, int stacks,
                                               persp_mesh *out);
PERSP_INTERNAL persp_status persp__mesh_cylinder(persp_context *ctx, int slices, persp_mesh *out);
PERSP_INTERNAL persp_status persp__mesh_torus(persp_context *ctx, float major, float minor,
                                              int slices, int rings, persp_mesh *out);
/* count unconnected triangles of sides in [size_min, size_max], each facing
 * +z within 45°, centred uniformly in [-1, 1]^3; the same seed gives the
 * same triangles (a fill-rate workload with overdraw). */
persp_status persp__mesh_soup(persp_context *ctx, int count, uint64_t seed, float size_min, float size_max,
                              persp_mesh *out);

/* Texture-coordinate generation (src/geom/texgen.c), per vertex, [CS300-TexMap]
 * "texture mapping entities" / lecture: object-linear (planar), cylindrical,
 * spherical, cube and reflection (sphere map; needs eye-space data).
 * modelview transforms object space to eye space. uv_out holds 2 floats per
 * vertex. PERSP_TEXGEN_UV copies the vertices' own uv. */
void persp__texgen_apply(const persp_object *obj, const persp_mat4 *modelview,
                         const persp_vertex *in, size_t count, float *uv_out);

#endif
