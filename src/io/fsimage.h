/*
   FSImage: a small 8-bit RGB raster with the few drawing operations the geometry view needs (exact
   colours, no antialiasing), and a PNG writer through libpng (src/io/png.c).

   Pixel (0, 0) is the top-left corner; x grows to the right, y downwards. Drawing outside the image
   is clipped. Private to flexslosh.
*/
#pragma once
#include <petscsys.h>

typedef struct {
  PetscInt       width, height;
  unsigned char *rgb; /* width*height*3 bytes, row-major from the top row */
} FSImage;

/* A map from world coordinates to pixels: world (x0, y0) at pixel (margin, height - 1 - margin) */
typedef struct {
  PetscReal x0, y0, scale;
  PetscInt  height, margin;
} FSImageMap;

static inline PetscReal FSImageMapX(const FSImageMap *m, PetscReal x) { return m->margin + (x - m->x0) * m->scale; }
static inline PetscReal FSImageMapY(const FSImageMap *m, PetscReal y)
{
  return (PetscReal)(m->height - 1 - m->margin) - (y - m->y0) * m->scale;
}

/* the nearest pixel */
static inline PetscInt FSImageRound(PetscReal v) { return (PetscInt)PetscFloorReal(v + 0.5); }

PETSC_INTERN PetscErrorCode FSImageCreate(PetscInt width, PetscInt height, FSImage *);
PETSC_INTERN PetscErrorCode FSImageDestroy(FSImage *);
PETSC_INTERN void           FSImageFill(FSImage *, const unsigned char rgb[3]);
PETSC_INTERN void           FSImageSetPixel(FSImage *, PetscInt x, PetscInt y, const unsigned char rgb[3]);
PETSC_INTERN void FSImageDrawLine(FSImage *, PetscInt x0, PetscInt y0, PetscInt x1, PetscInt y1, PetscInt thickness,
                                  const unsigned char rgb[3]);
PETSC_INTERN void FSImageDrawDisc(FSImage *, PetscReal cx, PetscReal cy, PetscReal radius, const unsigned char rgb[3]);
PETSC_INTERN PetscErrorCode FSImageWritePNG(MPI_Comm, const FSImage *, const char path[]);
