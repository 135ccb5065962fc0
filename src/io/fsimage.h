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

PETSC_INTERN PetscErrorCode FSImageCreate(PetscInt width, PetscInt height, FSImage *);
PETSC_INTERN PetscErrorCode FSImageDestroy(FSImage *);
PETSC_INTERN void           FSImageFill(FSImage *, const unsigned char rgb[3]);
PETSC_INTERN void           FSImageSetPixel(FSImage *, PetscInt x, PetscInt y, const unsigned char rgb[3]);
PETSC_INTERN void FSImageDrawLine(FSImage *, PetscInt x0, PetscInt y0, PetscInt x1, PetscInt y1, PetscInt thickness,
                                  const unsigned char rgb[3]);
PETSC_INTERN void FSImageDrawDisc(FSImage *, PetscReal cx, PetscReal cy, PetscReal radius, const unsigned char rgb[3]);
PETSC_INTERN PetscErrorCode FSImageWritePNG(MPI_Comm, const FSImage *, const char path[]);
