/*
   The raster of the geometry view (see fsimage.h): the few drawing operations it needs, done here
   pixel by pixel so that every colour stays exact (no antialiasing), and the PNG output through
   libpng (Debian libpng-dev): 8-bit RGB, not interlaced, libpng's default compression and filters
   and no time stamp, so the same image always gives the same bytes.
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <png.h>
#include "fsimage.h"
#include "fsoutput.h"

/* the palette of numbered things (fsimage.h) */
const unsigned char FSImagePalette[FS_IMAGE_NPALETTE][3] = {
    {40, 40, 40}, {170, 30, 30}, {0, 110, 50}, {120, 50, 160}, {180, 100, 0}, {0, 100, 120},
};

/*
   FSImageCreate - allocates a width x height image, filled with black.

   Not Collective
*/
PetscErrorCode FSImageCreate(PetscInt width, PetscInt height, FSImage *img)
{
  PetscFunctionBegin;
  PetscCheck(width > 0 && height > 0 && width <= 100000 && height <= 100000, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "Image size %" PetscInt_FMT " x %" PetscInt_FMT " is out of range: expected 1 to 100000 pixels a side",
             width, height);
  img->width  = width;
  img->height = height;
  PetscCall(PetscCalloc1((size_t)width * (size_t)height * 3, &img->rgb));
  PetscFunctionReturn(0);
}

/* FSImageDestroy - frees the pixels. Not Collective */
PetscErrorCode FSImageDestroy(FSImage *img)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(img->rgb));
  img->width = img->height = 0;
  PetscFunctionReturn(0);
}

/* FSImageFill - sets every pixel to rgb. */
void FSImageFill(FSImage *img, const unsigned char rgb[3])
{
  const size_t n = (size_t)img->width * (size_t)img->height;

  for (size_t k = 0; k < n; k++) memcpy(&img->rgb[3 * k], rgb, 3);
}

/* FSImageSetPixel - sets pixel (x, y) to rgb; pixels outside the image are ignored. */
void FSImageSetPixel(FSImage *img, PetscInt x, PetscInt y, const unsigned char rgb[3])
{
  if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
  memcpy(&img->rgb[3 * ((size_t)y * (size_t)img->width + (size_t)x)], rgb, 3);
}

/*
   FSImageDrawLine - draws the segment from (x0, y0) to (x1, y1) with Bresenham's algorithm (all
   octants, integer arithmetic), with a square pen of thickness x thickness pixels whose top-left
   corner follows the line (thickness 1 or 2 is what the geometry view uses).
*/
void FSImageDrawLine(FSImage *img, PetscInt x0, PetscInt y0, PetscInt x1, PetscInt y1, PetscInt thickness,
                     const unsigned char rgb[3])
{
  const PetscInt dx = x1 > x0 ? x1 - x0 : x0 - x1, sx = x0 < x1 ? 1 : -1;
  const PetscInt dy = y1 > y0 ? y0 - y1 : y1 - y0, sy = y0 < y1 ? 1 : -1; /* dy <= 0 */
  PetscInt       err = dx + dy, x = x0, y = y0;

  if (thickness < 1) thickness = 1;
  for (;;) {
    for (PetscInt j = 0; j < thickness; j++)
      for (PetscInt i = 0; i < thickness; i++) FSImageSetPixel(img, x + i, y + j, rgb);
    if (x == x1 && y == y1) break;
    {
      const PetscInt e2 = 2 * err;

      if (e2 >= dy) { /* step in x */
        err += dy;
        x += sx;
      }
      if (e2 <= dx) { /* step in y */
        err += dx;
        y += sy;
      }
    }
  }
}

/*
   FSImageDrawDisc - fills the pixels whose centres (pixel (i, j) has its centre at (i, j)) lie within
   radius of (cx, cy); the pixel nearest the centre is always set, so tiny discs stay visible.
*/
void FSImageDrawDisc(FSImage *img, PetscReal cx, PetscReal cy, PetscReal radius, const unsigned char rgb[3])
{
  const PetscInt i0 = (PetscInt)PetscFloorReal(cx - radius), i1 = (PetscInt)PetscCeilReal(cx + radius);
  const PetscInt j0 = (PetscInt)PetscFloorReal(cy - radius), j1 = (PetscInt)PetscCeilReal(cy + radius);

  FSImageSetPixel(img, (PetscInt)PetscFloorReal(cx + 0.5), (PetscInt)PetscFloorReal(cy + 0.5), rgb);
  for (PetscInt j = j0; j <= j1; j++)
    for (PetscInt i = i0; i <= i1; i++)
      if (PetscSqr((PetscReal)i - cx) + PetscSqr((PetscReal)j - cy) <= radius * radius) FSImageSetPixel(img, i, j, rgb);
}

/* where libpng writes, and the first error's reason */
typedef struct {
  FILE *fp;
  char  msg[256];
} FSPNGSink;

/* libpng's error callback: keeps the first reason and jumps back to FSPNGEncode's setjmp (an error
   callback must not return) */
static void FSPNGError(png_structp png, png_const_charp msg)
{
  FSPNGSink *sink = (FSPNGSink *)png_get_error_ptr(png);

  if (!sink->msg[0]) (void)snprintf(sink->msg, sizeof(sink->msg), "libpng: %s", msg);
  png_longjmp(png, 1);
}

/* libpng's warnings (nothing this writer does should raise one) are not errors: ignored */
static void FSPNGWarning(png_structp png, png_const_charp msg)
{
  (void)png;
  (void)msg;
}

/* libpng's output callbacks: stdio, with the system's reason kept when it fails */
static void FSPNGWrite(png_structp png, png_bytep data, size_t len)
{
  FSPNGSink *sink = (FSPNGSink *)png_get_io_ptr(png);

  if (fwrite(data, 1, len, sink->fp) != len) {
    if (!sink->msg[0]) (void)snprintf(sink->msg, sizeof(sink->msg), "%s", strerror(errno ? errno : EIO));
    png_error(png, "write failed");
  }
}

static void FSPNGFlush(png_structp png)
{
  FSPNGSink *sink = (FSPNGSink *)png_get_io_ptr(png);

  if (fflush(sink->fp) != 0) {
    if (!sink->msg[0]) (void)snprintf(sink->msg, sizeof(sink->msg), "%s", strerror(errno ? errno : EIO));
    png_error(png, "flush failed");
  }
}

/*
   Encodes img as PNG into sink->fp; returns 0, or 1 with the reason in sink->msg. libpng reports an
   error by a longjmp back to the setjmp below, so nothing between them calls PETSc (a jump must not
   skip a PetscFunctionReturn) or allocates; png and info are set before the setjmp and not changed
   after it, so they are valid after the jump.
*/
static int FSPNGEncode(const FSImage *img, FSPNGSink *sink)
{
  png_structp png  = png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, FSPNGError, FSPNGWarning);
  png_infop   info = png ? png_create_info_struct(png) : NULL;

  if (!png || !info) {
    png_destroy_write_struct(png ? &png : NULL, NULL);
    (void)snprintf(sink->msg, sizeof(sink->msg), "libpng: out of memory");
    return 1;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return 1;
  }
  png_set_write_fn(png, sink, FSPNGWrite, FSPNGFlush);
  png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (PetscInt y = 0; y < img->height; y++) png_write_row(png, img->rgb + (size_t)y * 3 * (size_t)img->width);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return 0;
}

/* Rank 0: writes img to tmp, then renames tmp to path; on failure, removes tmp and leaves the reason
   in msg (empty on success) */
static void FSImageWritePNGFile(const FSImage *img, const char tmp[], const char path[], char msg[], size_t len)
{
  FSPNGSink sink;
  FSFileId  id;
  int       err;

  msg[0]      = '\0';
  sink.msg[0] = '\0';
  if ((err = FSFileCreate_Private(tmp, &sink.fp, &id))) { /* not through a link under the name */
    (void)snprintf(msg, len, "%s", strerror(err));
    return;
  }
  if (FSPNGEncode(img, &sink)) (void)snprintf(msg, len, "%s", sink.msg[0] ? sink.msg : "libpng failed");
  if (fclose(sink.fp) != 0 && !msg[0]) (void)snprintf(msg, len, "%s", strerror(errno ? errno : EIO));
  if (!msg[0] && (err = FSFileReplace_Private(tmp, path, &id))) (void)snprintf(msg, len, "%s", strerror(err));
  if (msg[0]) (void)remove(tmp);
}

/*
   FSImageWritePNG - writes an image as an 8-bit RGB PNG file, under "<path>.tmp" renamed to path
   when complete.

   Collective

   Input Parameters:
+  comm - rank 0 of comm writes (img is only read there), the outcome is broadcast so every rank
          raises the same error; call with PETSC_COMM_SELF from code that runs on one rank
.  img  - the image
-  path - the file
*/
PetscErrorCode FSImageWritePNG(MPI_Comm comm, const FSImage *img, const char path[])
{
  char        tmp[PETSC_MAX_PATH_LEN], msg[256] = "";
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  if (rank == 0) FSImageWritePNGFile(img, tmp, path, msg, sizeof(msg));
  PetscCallMPI(MPI_Bcast(msg, (PetscMPIInt)sizeof(msg), MPI_CHAR, 0, comm));
  PetscCheck(!msg[0], comm, PETSC_ERR_FILE_WRITE, "Cannot write the picture \"%s\": %s", path, msg);
  PetscFunctionReturn(0);
}
