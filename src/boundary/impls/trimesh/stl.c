/*
   STL files (ASCII or binary) into a wall mesh: rank 0 reads and parses the file, every rank gets the
   triangles (or the error) by broadcast and adds them to its mesh, sharing the vertices of equal
   coordinates (STL repeats them in every facet) so that the triangles are connected.
*/
#include "mesh.h"
#include "sys/fssys.h"
#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <strings.h>
#include <sys/stat.h>

/* what rank 0 read: the solids' names, and per facet its 9 coordinates and its solid */
typedef struct {
  PetscInt nsolid, ntri, tcap;
  char (*name)[64];
  PetscReal *xyz;
  PetscInt  *solid;
} STLData;

static PetscErrorCode STLDataAddSolid(STLData *s, const char name[])
{
  char(*names)[64];

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(s->nsolid + 1, &names));
  if (s->nsolid) PetscCall(PetscArraycpy(names, s->name, s->nsolid));
  PetscCall(PetscStrncpy(names[s->nsolid], name, sizeof(names[0])));
  PetscCall(PetscFree(s->name));
  s->name = names;
  s->nsolid++;
  PetscFunctionReturn(0);
}

static PetscErrorCode STLDataAddFacet(STLData *s, const PetscReal xyz[9])
{
  PetscFunctionBegin;
  if (s->ntri == s->tcap) {
    PetscReal *x;
    PetscInt  *solid;
    s->tcap = PetscMax(64, 2 * s->tcap);
    PetscCall(PetscMalloc1(9 * s->tcap, &x));
    PetscCall(PetscMalloc1(s->tcap, &solid));
    if (s->ntri) {
      PetscCall(PetscArraycpy(x, s->xyz, 9 * s->ntri));
      PetscCall(PetscArraycpy(solid, s->solid, s->ntri));
    }
    PetscCall(PetscFree(s->xyz));
    PetscCall(PetscFree(s->solid));
    s->xyz   = x;
    s->solid = solid;
  }
  PetscCall(PetscArraycpy(&s->xyz[9 * s->ntri], xyz, 9));
  s->solid[s->ntri++] = s->nsolid - 1;
  PetscFunctionReturn(0);
}

static PetscErrorCode STLDataDestroy(STLData *s)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(s->name));
  PetscCall(PetscFree(s->xyz));
  PetscCall(PetscFree(s->solid));
  PetscCall(PetscMemzero(s, sizeof(*s)));
  PetscFunctionReturn(0);
}

/* the words of an ASCII file, with their line numbers */
typedef struct {
  const char *p, *end;
  PetscInt    line, last; /* the line of the current word, of the one before */
} Scanner;

/* the next word (its start and length; len 0 at the end of the file), line: the line it is on (at the
   end of the file: the last line with a word) */
static void NextWord(Scanner *sc, const char **w, size_t *len)
{
  sc->last = sc->line;
  while (sc->p < sc->end && isspace((unsigned char)*sc->p)) {
    if (*sc->p == '\n') sc->line++;
    sc->p++;
  }
  *w = sc->p;
  while (sc->p < sc->end && !isspace((unsigned char)*sc->p)) sc->p++;
  *len = (size_t)(sc->p - *w);
  if (!*len) sc->line = sc->last;
}

/* the rest of the current line, without the leading and trailing blanks, into s[n] */
static void RestOfLine(Scanner *sc, char s[], size_t n)
{
  const char *a, *b;
  size_t      len;
  while (sc->p < sc->end && *sc->p != '\n' && isspace((unsigned char)*sc->p)) sc->p++;
  a = sc->p;
  while (sc->p < sc->end && *sc->p != '\n') sc->p++;
  b = sc->p;
  while (b > a && isspace((unsigned char)b[-1])) b--;
  len = PetscMin((size_t)(b - a), n - 1);
  memcpy(s, a, len);
  s[len] = 0;
}

static PetscBool WordIs(const char w[], size_t len, const char key[])
{
  return (PetscBool)(len == strlen(key) && !strncasecmp(w, key, len));
}

/* the word (at most 40 characters of it) for an error message */
static void Quote(const char w[], size_t len, char s[64])
{
  if (!len) {
    snprintf(s, 64, "the end of the file");
    return;
  }
  snprintf(s, 64, "\"%.*s%s\"", (int)PetscMin(len, 40), w, len > 40 ? "..." : "");
}

/* parses an ASCII STL; err and msg[] tell a file that is not one */
static PetscErrorCode ParseASCII(const char path[], const char name[], const char *text, size_t size, STLData *s,
                                 PetscErrorCode *err, char msg[], size_t msglen)
{
  Scanner     sc = {text, text + size, 1, 1};
  const char *w;
  size_t      len;
  char        solid[256], found[64];
  PetscInt    facet = 0;

  PetscFunctionBegin;
  *err = 0;
#define EXPECT(key, what)                                                                                         \
  do {                                                                                                            \
    NextWord(&sc, &w, &len);                                                                                      \
    if (!WordIs(w, len, key)) {                                                                                   \
      Quote(w, len, found);                                                                                       \
      *err = PETSC_ERR_FILE_UNEXPECTED;                                                                           \
      snprintf(msg, msglen,                                                                                       \
               "%s:%" PetscInt_FMT ": expected \"%s\" %s, found %s (a truncated or broken ASCII STL file)", path, \
               sc.line, key, what, found);                                                                        \
      PetscFunctionReturn(0);                                                                                     \
    }                                                                                                             \
  } while (0)
  for (;;) {
    NextWord(&sc, &w, &len);
    if (!len) break;
    if (!WordIs(w, len, "solid")) {
      Quote(w, len, found);
      *err = PETSC_ERR_FILE_UNEXPECTED;
      snprintf(msg, msglen, "%s:%" PetscInt_FMT ": expected \"solid\" or the end of the file, found %s", path, sc.line,
               found);
      PetscFunctionReturn(0);
    }
    RestOfLine(&sc, solid, sizeof(solid));
    {
      const char *bad = FSWallNameProblem(solid[0] ? solid : name);
      if (bad) {
        *err = PETSC_ERR_FILE_UNEXPECTED;
        snprintf(msg, msglen, "%s:%" PetscInt_FMT ": bad wall name \"%.80s\" (%s): %s", path, sc.line,
                 solid[0] ? solid : name, solid[0] ? "the solid's name" : "an unnamed solid is named by the file", bad);
        PetscFunctionReturn(0);
      }
    }
    PetscCall(STLDataAddSolid(s, solid[0] ? solid : name));
    for (;;) {
      PetscReal xyz[9];
      char      where[128];
      snprintf(where, sizeof(where), "(facet %" PetscInt_FMT " of solid \"%s\")", facet, s->name[s->nsolid - 1]);
      NextWord(&sc, &w, &len);
      if (WordIs(w, len, "endsolid")) {
        RestOfLine(&sc, found, sizeof(found)); /* the name repeated, or nothing */
        break;
      }
      if (!WordIs(w, len, "facet")) {
        Quote(w, len, found);
        *err = PETSC_ERR_FILE_UNEXPECTED;
        snprintf(msg, msglen,
                 "%s:%" PetscInt_FMT ": expected \"facet\" or \"endsolid\" in solid \"%s\", found %s (a truncated or "
                 "broken ASCII STL file)",
                 path, sc.line, s->name[s->nsolid - 1], found);
        PetscFunctionReturn(0);
      }
      RestOfLine(&sc, found, sizeof(found)); /* "normal nx ny nz": the orientation comes from the vertex order */
      EXPECT("outer", where);
      EXPECT("loop", where);
      for (PetscInt k = 0; k < 3; k++) {
        EXPECT("vertex", where);
        for (PetscInt d = 0; d < 3; d++) {
          char  *e, num[64];
          double x;
          NextWord(&sc, &w, &len);
          len = PetscMin(len, sizeof(num) - 1);
          memcpy(num, w, len);
          num[len] = 0;
          x        = len ? strtod(num, &e) : 0;
          if (!len || *e || !isfinite(x)) {
            Quote(w, len, found);
            *err = PETSC_ERR_FILE_UNEXPECTED;
            snprintf(msg, msglen,
                     "%s:%" PetscInt_FMT ": expected the coordinates of a vertex (three finite numbers) %s, found %s",
                     path, sc.line, where, found);
            PetscFunctionReturn(0);
          }
          xyz[3 * k + d] = (PetscReal)x;
        }
      }
      EXPECT("endloop", where);
      EXPECT("endfacet", where);
      PetscCall(STLDataAddFacet(s, xyz));
      facet++;
    }
  }
#undef EXPECT
  PetscFunctionReturn(0);
}

static uint32_t U32(const unsigned char *b)
{
  return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

/* rank 0: reads the file into s, or sets err and msg[] */
static PetscErrorCode ReadSTL(const char path[], const char name[], STLData *s, PetscErrorCode *err, char msg[],
                              size_t msglen)
{
  FILE          *fp;
  unsigned char *buf = NULL;
  long           size;
  PetscBool      solid = PETSC_FALSE, text = PETSC_TRUE;
  uint32_t       count = 0;

  PetscFunctionBegin;
  *err = 0;
  fp   = fopen(path, "rb");
  if (!fp) {
    *err = PETSC_ERR_FILE_OPEN;
    snprintf(msg, msglen, "Cannot open the STL file \"%s\": %s", path, strerror(errno));
    PetscFunctionReturn(0);
  }
  { /* a directory opens, and seeks to a huge size */
    struct stat sb;
    if (fstat(fileno(fp), &sb) != 0 || !S_ISREG(sb.st_mode)) {
      *err = PETSC_ERR_FILE_READ;
      snprintf(msg, msglen, "Cannot read the STL file \"%s\": not a regular file", path);
      fclose(fp);
      PetscFunctionReturn(0);
    }
  }
  if (fseek(fp, 0, SEEK_END) || (size = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET)) {
    *err = PETSC_ERR_FILE_READ;
    snprintf(msg, msglen, "Cannot read the STL file \"%s\": %s", path, strerror(errno));
    fclose(fp);
    PetscFunctionReturn(0);
  }
  PetscCall(PetscMalloc1(size + 1, &buf));
  if (fread(buf, 1, (size_t)size, fp) != (size_t)size) {
    *err = PETSC_ERR_FILE_READ;
    snprintf(msg, msglen, "Cannot read the STL file \"%s\" (%ld bytes): %s", path, size, strerror(errno));
    fclose(fp);
    PetscCall(PetscFree(buf));
    PetscFunctionReturn(0);
  }
  fclose(fp);
  buf[size] = 0;
  /* binary if the size is that of the facet count in the header (a binary header may start with "solid"),
     else ASCII if it reads as text starting with "solid" */
  if (size >= 84) count = U32(buf + 80);
  for (long k = 0; k < PetscMin(size, 1024); k++)
    if (buf[k] < 128 && !isprint(buf[k]) && !isspace(buf[k])) text = PETSC_FALSE;
  {
    long k = 0;
    while (k < size && isspace(buf[k])) k++;
    solid = (PetscBool)(size - k >= 5 && !strncasecmp((const char *)buf + k, "solid", 5));
  }
  if (size >= 84 && (uint64_t)size == 84 + 50 * (uint64_t)count) {
    const char *bad = FSWallNameProblem(name);
    if (bad) {
      *err = PETSC_ERR_FILE_UNEXPECTED;
      snprintf(msg, msglen, "%s: bad wall name \"%.80s\" (a binary STL file is named by the file): %s", path, name,
               bad);
      PetscCall(PetscFree(buf));
      PetscFunctionReturn(0);
    }
    PetscCall(STLDataAddSolid(s, name));
    for (uint32_t t = 0; t < count; t++) {
      const unsigned char *f = buf + 84 + 50 * (size_t)t + 12; /* the normal skipped */
      PetscReal            xyz[9];
      for (PetscInt k = 0; k < 9; k++) {
        const uint32_t u = U32(f + 4 * k);
        float          x;
        memcpy(&x, &u, sizeof(x));
        if (!isfinite(x)) {
          *err = PETSC_ERR_FILE_UNEXPECTED;
          snprintf(msg, msglen, "%s: triangle %u of the binary STL file has a coordinate that is not a finite number",
                   path, t);
          PetscCall(PetscFree(buf));
          PetscFunctionReturn(0);
        }
        xyz[k] = (PetscReal)x;
      }
      PetscCall(STLDataAddFacet(s, xyz));
    }
  } else if (FSTextByteOrderMark((const char *)buf, (size_t)size)) { /* an ASCII STL saved with a mark */
    *err = PETSC_ERR_FILE_UNEXPECTED;
    snprintf(msg, msglen, "%s:1: the file starts with %s: save it as plain text, ASCII or UTF-8 without the mark", path,
             FSTextByteOrderMark((const char *)buf, (size_t)size));
  } else if (solid && text) {
    PetscCall(ParseASCII(path, name, (const char *)buf, (size_t)size, s, err, msg, msglen));
  } else if (size >= 84) {
    *err = PETSC_ERR_FILE_UNEXPECTED;
    snprintf(
        msg, msglen,
        "%s: a binary STL file (not an ASCII one: %s) of %u triangles (the count in its header) has 84 + 50 x %u = "
        "%llu bytes, but the file has %ld bytes: truncated, or not an STL file",
        path, solid ? "it is not text" : "it does not start with \"solid\"", count, count,
        (unsigned long long)(84 + 50 * (uint64_t)count), size);
  } else {
    *err = PETSC_ERR_FILE_UNEXPECTED;
    snprintf(msg, msglen,
             "%s: not an STL file (%ld bytes): an ASCII STL starts with \"solid\", a binary one has an 84-byte header",
             path, size);
  }
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

/* an open-addressing hash of the mesh's vertices by their exact coordinates */
typedef struct {
  PetscInt  size, n; /* size: a power of 2 */
  PetscInt *slot;    /* a vertex index, -1 for an empty slot */
} VertexHash;

static uint64_t HashPoint(const PetscReal x[3])
{
  uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (PetscInt d = 0; d < 3; d++) {
    double   v = (double)x[d] + 0.0; /* -0 and 0 alike */
    uint64_t b;
    memcpy(&b, &v, sizeof(b));
    h ^= b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 29;
  }
  return h;
}

static void VertexHashPut(VertexHash *h, const FSMesh *m, PetscInt v)
{
  PetscInt k = (PetscInt)(HashPoint(&m->vert[3 * v]) & (uint64_t)(h->size - 1));
  while (h->slot[k] >= 0) k = (k + 1) & (h->size - 1);
  h->slot[k] = v;
  h->n++;
}

static PetscErrorCode VertexHashResize(VertexHash *h, const FSMesh *m, PetscInt size)
{
  PetscInt *old = h->slot, oldsize = h->size;

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(size, &h->slot));
  for (PetscInt k = 0; k < size; k++) h->slot[k] = -1;
  h->size = size;
  h->n    = 0;
  for (PetscInt k = 0; k < oldsize; k++)
    if (old[k] >= 0) VertexHashPut(h, m, old[k]);
  PetscCall(PetscFree(old));
  PetscFunctionReturn(0);
}

/* the vertex of m at x, added if m has none there */
static PetscErrorCode VertexHashFind(VertexHash *h, FSMesh *m, const PetscReal x[3], PetscInt *v)
{
  PetscInt k;

  PetscFunctionBegin;
  if (2 * (h->n + 1) > h->size) PetscCall(VertexHashResize(h, m, 2 * h->size));
  k = (PetscInt)(HashPoint(x) & (uint64_t)(h->size - 1));
  for (; h->slot[k] >= 0; k = (k + 1) & (h->size - 1)) {
    const PetscReal *y = &m->vert[3 * h->slot[k]];
    if (y[0] == x[0] && y[1] == x[1] && y[2] == x[2]) {
      *v = h->slot[k];
      PetscFunctionReturn(0);
    }
  }
  PetscCall(FSMeshAddVertex(m, x, v));
  h->slot[k] = *v;
  h->n++;
  PetscFunctionReturn(0);
}

/*
   FSMeshLoadSTL - adds the triangles of an STL file, ASCII or binary (told apart by content: binary
   if the file's size is 84 + 50 times the facet count in its header, else ASCII if it is text starting
   with "solid"). Each solid of an ASCII file is a wall part named by its solid name (name if it has
   none); a binary file is one wall part, name. The facets' normals are ignored: a triangle's
   orientation is that of its vertex order (right-hand rule). Vertices of equal coordinates are shared
   (with those already in the mesh too). Each triangle records its facet number in the file (0-based),
   each new wall the file, for the error messages of FSMeshCheck.

   Collective: rank 0 reads the file and broadcasts the triangles, or its error, which every rank then
   raises on comm (a missing or unreadable file, a binary file of the wrong size, an ASCII file that
   does not parse: named with the line)

   Input Parameters:
+  m    - the mesh
.  comm - the communicator
.  path - the file
-  name - the wall of a binary file or an unnamed solid (NULL or "": the file's name without its folder
          and extension)

.seealso: FSMeshCheck(), FSMeshExtrude()
*/
PetscErrorCode FSMeshLoadSTL(FSMesh *m, MPI_Comm comm, const char path[], const char name[])
{
  STLData     s;
  PetscMPIInt rank;
  PetscInt    hdr[3]    = {0, 0, 0}, *wall;
  char        msg[1024] = "", defname[64];
  VertexHash  h         = {0, 0, NULL};

  PetscFunctionBegin;
  PetscCall(PetscMemzero(&s, sizeof(s)));
  if (!name || !name[0]) {
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    char       *dot;
    PetscCall(PetscStrncpy(defname, base, sizeof(defname)));
    if ((dot = strrchr(defname, '.')) && dot != defname) *dot = 0;
    name = defname;
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    PetscErrorCode err;
    PetscCall(ReadSTL(path, name, &s, &err, msg, sizeof(msg)));
    hdr[0] = err;
    hdr[1] = s.nsolid;
    hdr[2] = s.ntri;
  }
  PetscCallMPI(MPI_Bcast(hdr, 3, MPIU_INT, 0, comm));
  if (hdr[0]) {
    PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, 0, comm));
    PetscCall(STLDataDestroy(&s));
    SETERRQ(comm, (PetscErrorCode)hdr[0], "%s", msg);
  }
  if (rank) {
    s.nsolid = hdr[1];
    s.ntri   = hdr[2];
    PetscCall(PetscMalloc1(s.nsolid, &s.name));
    PetscCall(PetscMalloc1(9 * s.ntri, &s.xyz));
    PetscCall(PetscMalloc1(s.ntri, &s.solid));
  }
  PetscCallMPI(MPI_Bcast(s.name, (PetscMPIInt)(64 * s.nsolid), MPI_CHAR, 0, comm));
  PetscCallMPI(MPI_Bcast(s.xyz, (PetscMPIInt)(9 * s.ntri), MPIU_REAL, 0, comm));
  PetscCallMPI(MPI_Bcast(s.solid, (PetscMPIInt)s.ntri, MPIU_INT, 0, comm));

  PetscCall(PetscMalloc1(s.nsolid, &wall));
  for (PetscInt k = 0; k < s.nsolid; k++) PetscCall(FSMeshAddWall(m, s.name[k], path, &wall[k]));
  {
    PetscInt size = 64;
    while (size < 2 * (m->nvert + s.ntri)) size *= 2; /* about ntri/2 new vertices */
    PetscCall(VertexHashResize(&h, m, size));
  }
  for (PetscInt v = 0; v < m->nvert; v++) VertexHashPut(&h, m, v);
  for (PetscInt t = 0; t < s.ntri; t++) {
    PetscInt v[3];
    for (PetscInt k = 0; k < 3; k++) PetscCall(VertexHashFind(&h, m, &s.xyz[9 * t + 3 * k], &v[k]));
    PetscCall(FSMeshAddTriangle(m, wall[s.solid[t]], v[0], v[1], v[2], t));
  }
  PetscCall(PetscFree(h.slot));
  PetscCall(PetscFree(wall));
  PetscCall(STLDataDestroy(&s));
  PetscFunctionReturn(0);
}
