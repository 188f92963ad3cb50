/* Confinement of the harnesses' file access to tests/fuzz/files/ (confine.c). */
#ifndef PERSP_FUZZ_CONFINE_H
#define PERSP_FUZZ_CONFINE_H

/* 1: from now on persp may open files in tests/fuzz/files/ only; 0: any. */
void fuzz_confine(int on);

#endif
