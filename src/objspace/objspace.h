/* Entry point of the object-space pipeline (internal). */
#ifndef PERSP_OBJSPACE_OBJSPACE_H
#define PERSP_OBJSPACE_OBJSPACE_H

#include "raster/frame.h"

/* Object-space texturing with screen-space filtering ([Romaniuk-ObjSpace]), run after
 * the screen pipeline has filled fb and cap (visible triangle per pixel):
 * re-colours every pixel from splatted texels (src/objspace/objspace.c). */
typedef struct persp_objspace_stats {
    uint64_t splats, texels_walked, holes, triangles_split, pieces;
    uint64_t visited;     /* rows and samples the walk stepped through */
    double work_estimate; /* the same, estimated before the walk */
} persp_objspace_stats;
persp_status persp__objspace_resolve(persp_frame *f, const persp_capture *cap,
                                     persp_objspace_stats *stats);

#endif
