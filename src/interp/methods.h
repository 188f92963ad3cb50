/* Method entries of the registry; one extern per method (src/interp/registry.c). */
#ifndef PERSP_INTERP_METHODS_H
#define PERSP_INTERP_METHODS_H

#include "interp/method.h"

/* Plane p(x,y) = px·x + py·y + pc through three (x, y, value) points. */
void persp__plane_through(const double vx[3], const double vy[3], const double val[3],
                          double *px, double *py, double *pc);

extern const persp_method persp__method_affine;
extern const persp_method persp__method_exact;

#endif
