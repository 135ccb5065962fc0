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

/*
   A map from world coordinates to pixels, for one view of the world: the world axis ax (0, 1, 2 for
   x, y, z) along the pixel x axis and the world axis ay along the pixel y axis, the point (x0, y0) of
   those axes at pixel (i0, j0), scale pixels per world unit. The axis ay grows upwards in the
   picture (down = PETSC_FALSE), or downwards (down = PETSC_TRUE: z in a view from above with x to
   the right). A 2-D picture maps ax = 0, ay = 1, upwards.
*/
typedef struct {
  PetscReal x0, y0, scale;
  PetscReal i0, j0;
  PetscInt  ax, ay;
  PetscBool down;
} FSImageMap;

/* the pixel x of the world coordinate x along the map's axis ax, and the pixel y of y along ay */
static inline PetscReal FSImageMapX(const FSImageMap *m, PetscReal x) { return m->i0 + (x - m->x0) * m->scale; }
static inline PetscReal FSImageMapY(const FSImageMap *m, PetscReal y)
{
  return m->down ? m->j0 + (y - m->y0) * m->scale : m->j0 - (y - m->y0) * m->scale;
}
/* the pixel (px, py) of a world point p (2 or 3 coordinates; those of the map's axes are used) */
static inline void FSImageMapPoint(const FSImageMap *m, const PetscReal p[], PetscReal *px, PetscReal *py)
{
  *px = FSImageMapX(m, p[m->ax]);
  *py = FSImageMapY(m, p[m->ay]);
}

/* Colours told apart easily on white and from the geometry view's blue particles, for numbered
   things (the walls of the geometry view: wall k in colour k % FS_IMAGE_NPALETTE): dark grey, red,
   green, purple, orange, teal (tests/python/test_geometry_view.py checks them) */
#define FS_IMAGE_NPALETTE 6
PETSC_INTERN const unsigned char FSImagePalette[FS_IMAGE_NPALETTE][3];

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
