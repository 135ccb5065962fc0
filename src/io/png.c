/*
   A minimal PNG writer and raster helpers (see fsimage.h), written from the PNG specification
   (ISO/IEC 15948, W3C PNG 2nd edition) and RFC 1950/1951 for the zlib stream:

     file    = signature (8 bytes) IHDR IDAT IEND
     chunk   = length (4, big-endian, data only) type (4) data CRC-32 (4, over type and data)
     IHDR    = width (4) height (4) bit depth 8, colour type 2 (RGB), compression 0, filter 0,
               interlace 0
     IDAT    = one zlib stream: CMF 0x78 (deflate, 32K window), FLG 0x01 (no dictionary, fastest;
               0x7801 is a multiple of 31), stored deflate blocks (a header byte with BFINAL in
               bit 0 and BTYPE 00, then LEN and ~LEN as 16-bit little-endian, then LEN <= 65535 raw
               bytes), then the Adler-32 of the raw data (big-endian)
     raw     = per row: filter type 0 (None), then width*3 bytes R, G, B

   Stored blocks make the file about as large as the raster (3 bytes a pixel), which is fine for the
   set-up pictures this writes. The same image always gives the same bytes.
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include "fsimage.h"

#define FS_PNG_STORED_MAX 65535

/* CRC-32 of PNG and zlib (ISO 3309, reflected polynomial 0xedb88320), table built on first use */
static unsigned long FSCRCTable[256];
static int           FSCRCTableReady = 0;

static void FSCRCInitTable(void)
{
  for (unsigned long n = 0; n < 256; n++) {
    unsigned long c = n;
    for (int k = 0; k < 8; k++) c = (c & 1) ? 0xedb88320UL ^ (c >> 1) : c >> 1;
    FSCRCTable[n] = c;
  }
  FSCRCTableReady = 1;
}

/* running CRC: start from crc = 0 (the pre- and post-conditioning with 0xffffffff is inside) */
static unsigned long FSCRC32(unsigned long crc, const unsigned char *buf, size_t len)
{
  unsigned long c = crc ^ 0xffffffffUL;

  if (!FSCRCTableReady) FSCRCInitTable();
  for (size_t i = 0; i < len; i++) c = FSCRCTable[(c ^ buf[i]) & 0xff] ^ (c >> 8);
  return (c ^ 0xffffffffUL) & 0xffffffffUL;
}

/* Adler-32 of RFC 1950: start from adler = 1; the sums are reduced modulo 65521 every 5552 bytes,
   the most that cannot overflow 32 bits */
static unsigned long FSAdler32(unsigned long adler, const unsigned char *buf, size_t len)
{
  unsigned long a = adler & 0xffff, b = (adler >> 16) & 0xffff;

  while (len > 0) {
    size_t n = len < 5552 ? len : 5552;

    len -= n;
    while (n--) {
      a += *buf++;
      b += a;
    }
    a %= 65521;
    b %= 65521;
  }
  return (b << 16) | a;
}

static unsigned char *FSPut32(unsigned char *p, unsigned long v)
{
  p[0] = (unsigned char)((v >> 24) & 0xff);
  p[1] = (unsigned char)((v >> 16) & 0xff);
  p[2] = (unsigned char)((v >> 8) & 0xff);
  p[3] = (unsigned char)(v & 0xff);
  return p + 4;
}

/* writes a chunk's length and type at p, expects its len data bytes to follow, then appends the CRC;
   returns the end of the chunk */
static unsigned char *FSPutChunk(unsigned char *p, const char type[4], size_t len)
{
  unsigned char *t = p + 4;

  p = FSPut32(p, (unsigned long)len);
  memcpy(t, type, 4);
  return FSPut32(t + 4 + len, FSCRC32(0, t, len + 4));
}

/*
   FSImageCreate - allocates a width x height image, filled with black.

   Not Collective
*/
PetscErrorCode FSImageCreate(PetscInt width, PetscInt height, FSImage *img)
{
  PetscFunctionBegin;
  PetscCheck(width > 0 && height > 0 && width <= 100000 && height <= 100000, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Image size %" PetscInt_FMT " x %" PetscInt_FMT " is out of range: expected 1 to 100000 pixels a side", width, height);
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
void FSImageDrawLine(FSImage *img, PetscInt x0, PetscInt y0, PetscInt x1, PetscInt y1, PetscInt thickness, const unsigned char rgb[3])
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

/* Rank 0: encodes img and writes it to tmp, then renames tmp to path; returns an errno value */
static PetscErrorCode FSImageWritePNGFile(const FSImage *img, const char tmp[], const char path[], int *ioerr)
{
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const size_t               rowlen = 1 + 3 * (size_t)img->width, rawlen = rowlen * (size_t)img->height;
  const size_t               nblocks = (rawlen + FS_PNG_STORED_MAX - 1) / FS_PNG_STORED_MAX;
  const size_t               zlen = 2 + 5 * nblocks + rawlen + 4;
  const size_t               total = 8 + (12 + 13) + (12 + zlen) + 12;
  unsigned char             *buf, *p, *z, *raw;
  unsigned long              adler = 1;
  FILE                      *fp;

  PetscFunctionBegin;
  *ioerr = 0;
  PetscCheck(zlen <= 0x7fffffffUL, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "Image %" PetscInt_FMT " x %" PetscInt_FMT " is too large for one PNG chunk", img->width, img->height);
  PetscCall(PetscMalloc2(total, &buf, rowlen, &raw));
  memcpy(buf, sig, 8);
  p = buf + 8;
  /* IHDR */
  FSPut32(p + 8, (unsigned long)img->width);
  FSPut32(p + 12, (unsigned long)img->height);
  p[16] = 8; /* bit depth */
  p[17] = 2; /* colour type: RGB */
  p[18] = 0; /* compression: deflate */
  p[19] = 0; /* filter method 0 */
  p[20] = 0; /* no interlace */
  p     = FSPutChunk(p, "IHDR", 13);
  /* IDAT: the zlib stream, the raw rows fed block by block */
  z    = p + 8;
  *z++ = 0x78;
  *z++ = 0x01;
  {
    size_t done = 0, inblock = 0, row = 0, inrow = rowlen; /* inrow = rowlen: the next row must be made */
    while (done < rawlen) {
      const size_t blen = rawlen - done < FS_PNG_STORED_MAX ? rawlen - done : FS_PNG_STORED_MAX;

      *z++ = (unsigned char)(done + blen == rawlen ? 1 : 0); /* BFINAL on the last block, BTYPE 00 */
      *z++ = (unsigned char)(blen & 0xff);
      *z++ = (unsigned char)(blen >> 8);
      *z++ = (unsigned char)(~blen & 0xff);
      *z++ = (unsigned char)((~blen >> 8) & 0xff);
      for (inblock = 0; inblock < blen;) {
        size_t n;

        if (inrow == rowlen) { /* next row: filter byte 0, then the pixels */
          raw[0] = 0;
          memcpy(raw + 1, &img->rgb[row * 3 * (size_t)img->width], 3 * (size_t)img->width);
          row++;
          inrow = 0;
        }
        n = rowlen - inrow < blen - inblock ? rowlen - inrow : blen - inblock;
        memcpy(z, raw + inrow, n);
        adler = FSAdler32(adler, raw + inrow, n);
        z += n;
        inrow += n;
        inblock += n;
      }
      done += blen;
    }
  }
  z = FSPut32(z, adler);
  PetscCheck((size_t)(z - (p + 8)) == zlen, PETSC_COMM_SELF, PETSC_ERR_PLIB, "PNG encoder: zlib stream is %zu bytes, expected %zu", (size_t)(z - (p + 8)), zlen);
  p = FSPutChunk(p, "IDAT", zlen);
  p = FSPutChunk(p, "IEND", 0);
  PetscCheck((size_t)(p - buf) == total, PETSC_COMM_SELF, PETSC_ERR_PLIB, "PNG encoder: file is %zu bytes, expected %zu", (size_t)(p - buf), total);

  fp = fopen(tmp, "wb");
  if (!fp) *ioerr = errno ? errno : EIO;
  else {
    if (fwrite(buf, 1, total, fp) != total) *ioerr = errno ? errno : EIO;
    if (fclose(fp) != 0 && !*ioerr) *ioerr = errno ? errno : EIO;
    if (!*ioerr && rename(tmp, path) != 0) *ioerr = errno ? errno : EIO;
    if (*ioerr) (void)remove(tmp);
  }
  PetscCall(PetscFree2(buf, raw));
  PetscFunctionReturn(0);
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
  char        tmp[PETSC_MAX_PATH_LEN];
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  if (rank == 0) PetscCall(FSImageWritePNGFile(img, tmp, path, &err));
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot write the picture \"%s\": %s", path, strerror(err));
  PetscFunctionReturn(0);
}
