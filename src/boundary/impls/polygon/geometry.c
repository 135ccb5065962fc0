/*
   Wall geometry (2-D): named closed polygons, their checks (closed, simple, consistently oriented,
   nested), built-in tanks, the polyline file format, and the discretization into segments.
*/
#include "walls.h"
#include "sys/fssys.h"
#include <ctype.h>

PetscErrorCode FSWallsCreate(FSWalls *w)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(w, sizeof(*w)));
  PetscCall(PetscMalloc1(1, &w->pstart));
  w->pstart[0] = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode FSWallsDestroy(FSWalls *w)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(w->pstart));
  PetscCall(PetscFree(w->pwall));
  PetscCall(PetscFree(w->vwall));
  PetscCall(PetscFree(w->vert));
  PetscCall(PetscFree(w->area));
  PetscCall(PetscFree(w->where));
  PetscCall(PetscFree(w->name));
  PetscCall(PetscFree(w->seg));
  PetscCall(PetscFree(w->segwall));
  PetscFunctionReturn(0);
}

/*
   FSWallNameProblem - NULL if name can name a wall, else what is wrong with it. A wall's name becomes
   column names of timeseries.csv (wall_<name>_force_x, ...), an item of the comma-separated list in
   walls.xdmf and walls.h5, and of -fs_walls_noslip: 1 to 63 printable ASCII characters, no comma, quote,
   '<', '>' or '&', no blank at either end (STL solid names may hold blanks inside).
*/
const char *FSWallNameProblem(const char name[])
{
  const size_t n = strlen(name);
  if (!n) return "a name is empty";
  if (n > 63) return "a name has at most 63 characters";
  if (name[0] == ' ' || name[n - 1] == ' ') return "a name neither starts nor ends with a blank";
  for (size_t k = 0; k < n; k++) {
    const unsigned char c = (unsigned char)name[k];
    if (c < 0x20 || c > 0x7e) return "a name has printable ASCII characters only";
    if (strchr(",\"'<>&", c)) return "a name has no comma, quote, '<', '>' or '&' (it names CSV columns and XML items)";
  }
  return NULL;
}

static PetscReal Cross(const PetscReal a[], const PetscReal b[], const PetscReal c[])
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Do the closed segments ab and cd intersect (touching included)? */
static PetscBool SegmentsIntersect(const PetscReal a[], const PetscReal b[], const PetscReal c[], const PetscReal d[])
{
  const PetscReal d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  const PetscReal scale = PetscMax(PetscMax(PetscAbsReal(b[0] - a[0]), PetscAbsReal(b[1] - a[1])),
                                   PetscMax(PetscAbsReal(d[0] - c[0]), PetscAbsReal(d[1] - c[1])));
  const PetscReal eps   = 1e-12 * scale * scale;
  if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps)))
    return PETSC_TRUE;
  /* collinear or touching cases */
  {
    const PetscReal *pts[4] = {a, b, c, d};
    const PetscReal  cr[4]  = {d1, d2, d3, d4};
    for (PetscInt k = 0; k < 4; k++) {
      const PetscReal *p = pts[k], *s0 = k < 2 ? c : a, *s1 = k < 2 ? d : b;
      if (PetscAbsReal(cr[k]) <= eps && p[0] >= PetscMin(s0[0], s1[0]) - 1e-12 * scale &&
          p[0] <= PetscMax(s0[0], s1[0]) + 1e-12 * scale && p[1] >= PetscMin(s0[1], s1[1]) - 1e-12 * scale &&
          p[1] <= PetscMax(s0[1], s1[1]) + 1e-12 * scale)
        return PETSC_TRUE;
    }
  }
  return PETSC_FALSE;
}

/* Is x inside polygon p (even-odd rule)? */
static PetscBool InPolygon(const FSWalls *w, PetscInt p, const PetscReal x[])
{
  PetscBool in = PETSC_FALSE;
  PetscInt  s = w->pstart[p], n = w->pstart[p + 1] - s;
  for (PetscInt i = 0, j = n - 1; i < n; j = i++) {
    const PetscReal *a = &w->vert[2 * (s + i)], *b = &w->vert[2 * (s + j)];
    if ((a[1] > x[1]) != (b[1] > x[1]) && x[0] < (b[0] - a[0]) * (x[1] - a[1]) / (b[1] - a[1]) + a[0])
      in = (PetscBool)!in;
  }
  return in;
}

/* the index of the wall named name, added if new */
static PetscErrorCode FSWallsFindOrAdd(FSWalls *w, const char name[], PetscInt *wall)
{
  PetscFunctionBegin;
  *wall = -1;
  for (PetscInt k = 0; k < w->nwalls; k++)
    if (!strcmp(w->name[k], name)) *wall = k;
  if (*wall < 0) {
    char(*names)[64];
    PetscCall(PetscMalloc1(w->nwalls + 1, &names));
    if (w->nwalls) PetscCall(PetscArraycpy(names, w->name, w->nwalls));
    PetscCall(PetscStrncpy(names[w->nwalls], name, 64));
    PetscCall(PetscFree(w->name));
    w->name = names;
    *wall   = w->nwalls++;
  }
  PetscFunctionReturn(0);
}

/*
   FSWallsAddPolygon - adds a closed polygon to the wall named name (created if new). The last
   vertex connects back to the first (a repeated first vertex is dropped). where names the origin
   of the data in error messages (a file and line, or an option).
*/
PetscErrorCode FSWallsAddPolygon(FSWalls *w, MPI_Comm comm, const char name[], PetscInt n, const PetscReal xy[],
                                 const char where[])
{
  PetscInt  wall = -1, s;
  PetscReal area = 0;

  PetscFunctionBegin;
  if (n > 1 && xy[0] == xy[2 * (n - 1)] && xy[1] == xy[2 * (n - 1) + 1]) n--;
  PetscCheck(n >= 3, comm, PETSC_ERR_ARG_WRONG,
             "Wall \"%s\" (%s) has %" PetscInt_FMT
             " distinct vertices: a wall is a closed polygon of at least 3 vertices",
             name, where, n);
  PetscCall(FSWallsFindOrAdd(w, name, &wall));
  /* grow the arrays */
  {
    PetscInt  *pstart, *pwall;
    PetscInt  *vwall;
    PetscReal *vert, *ar;
    char(*wh)[FS_WALLS_WHERE_LEN];
    PetscCall(PetscMalloc1(w->npoly + 1, &wh));
    if (w->npoly) PetscCall(PetscArraycpy(wh, w->where, w->npoly));
    PetscCall(PetscFree(w->where));
    w->where = wh;
    PetscCall(PetscMalloc1(w->npoly + 2, &pstart));
    PetscCall(PetscMalloc1(w->nvert + n, &vwall));
    PetscCall(PetscMalloc1(w->npoly + 1, &pwall));
    PetscCall(PetscMalloc1(w->npoly + 1, &ar));
    PetscCall(PetscMalloc1(2 * (w->nvert + n), &vert));
    PetscCall(PetscArraycpy(pstart, w->pstart, w->npoly + 1));
    if (w->npoly) {
      PetscCall(PetscArraycpy(pwall, w->pwall, w->npoly));
      PetscCall(PetscArraycpy(ar, w->area, w->npoly));
    }
    if (w->nvert) {
      PetscCall(PetscArraycpy(vert, w->vert, 2 * w->nvert));
      PetscCall(PetscArraycpy(vwall, w->vwall, w->nvert));
    }
    PetscCall(PetscFree(w->vwall));
    PetscCall(PetscFree(w->pstart));
    PetscCall(PetscFree(w->pwall));
    PetscCall(PetscFree(w->area));
    PetscCall(PetscFree(w->vert));
    w->pstart = pstart;
    w->pwall  = pwall;
    w->area   = ar;
    w->vert   = vert;
    w->vwall  = vwall;
  }
  s = w->nvert;
  for (PetscInt k = 0; k < n; k++) {
    w->vert[2 * (s + k)]     = xy[2 * k];
    w->vert[2 * (s + k) + 1] = xy[2 * k + 1];
    PetscCheck(!PetscIsInfOrNanReal(xy[2 * k]) && !PetscIsInfOrNanReal(xy[2 * k + 1]), comm, PETSC_ERR_ARG_WRONG,
               "Wall \"%s\" (%s): vertex %" PetscInt_FMT " (%g, %g) is not a pair of finite numbers", name, where, k,
               (double)xy[2 * k], (double)xy[2 * k + 1]);
  }
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *a = &xy[2 * k], *b = &xy[2 * ((k + 1) % n)];
    area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
  }
  /* a simple polygon: no two non-adjacent edges meet, no zero-length edge */
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *a = &xy[2 * i], *b = &xy[2 * ((i + 1) % n)];
    PetscCheck(a[0] != b[0] || a[1] != b[1], comm, PETSC_ERR_ARG_WRONG,
               "Wall \"%s\" (%s): vertices %" PetscInt_FMT " and %" PetscInt_FMT " coincide", name, where, i,
               (i + 1) % n);
    for (PetscInt j = i + 2; j < n; j++) {
      const PetscReal *c = &xy[2 * j], *d = &xy[2 * ((j + 1) % n)];
      if ((j + 1) % n == i) continue; /* adjacent through the closing edge */
      PetscCheck(!SegmentsIntersect(a, b, c, d), comm, PETSC_ERR_ARG_WRONG,
                 "Wall \"%s\" (%s) intersects itself: edge %" PetscInt_FMT " (%g,%g)-(%g,%g) meets edge %" PetscInt_FMT
                 " (%g,%g)-(%g,%g)",
                 name, where, i, (double)a[0], (double)a[1], (double)b[0], (double)b[1], j, (double)c[0], (double)c[1],
                 (double)d[0], (double)d[1]);
    }
  }
  PetscCheck(area != 0, comm, PETSC_ERR_ARG_WRONG, "Wall \"%s\" (%s) encloses no area", name, where);
  for (PetscInt k = 0; k < n; k++) w->vwall[s + k] = wall;
  w->pwall[w->npoly] = wall;
  w->area[w->npoly]  = area;
  PetscCall(PetscStrncpy(w->where[w->npoly], where, sizeof(w->where[0])));
  w->nvert += n;
  w->pstart[++w->npoly] = w->nvert;
  PetscFunctionReturn(0);
}

/*
   FSWallsSetEdgeWall - gives edge e of polygon p (from its vertex e to the next) to the wall named
   name (added if new), so that one polygon carries walls of different names and properties: a tank
   whose floor is no-slip and whose sides are free-slip, the load on the floor alone.
*/
PetscErrorCode FSWallsSetEdgeWall(FSWalls *w, MPI_Comm comm, PetscInt p, PetscInt e, const char name[])
{
  PetscInt wall;

  PetscFunctionBegin;
  PetscCheck(p >= 0 && p < w->npoly, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Polygon %" PetscInt_FMT " does not exist (%" PetscInt_FMT " polygons)", p, w->npoly);
  PetscCheck(e >= 0 && e < w->pstart[p + 1] - w->pstart[p], comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Polygon %" PetscInt_FMT " has no edge %" PetscInt_FMT " (%" PetscInt_FMT " edges)", p, e,
             w->pstart[p + 1] - w->pstart[p]);
  PetscCall(FSWallsFindOrAdd(w, name, &wall));
  w->vwall[w->pstart[p] + e] = wall;
  PetscFunctionReturn(0);
}

/*
   FSWallsCheck - the polygons together: the first (the container) runs counter-clockwise and holds
   all the others, which run clockwise (liquid outside them), lie inside it and do not meet each
   other. A wrong orientation is reported as inconsistent normals.
*/
PetscErrorCode FSWallsCheck(FSWalls *w, MPI_Comm comm)
{
  PetscFunctionBegin;
  PetscCheck(w->npoly > 0, comm, PETSC_ERR_ARG_WRONG, "No walls given");
  PetscCheck(
      w->area[0] > 0, comm, PETSC_ERR_ARG_WRONG,
      "Inconsistent normals: the container wall \"%s\" (%s, the first polygon) runs clockwise; list its vertices "
      "counter-clockwise so that the liquid is on the left of each edge",
      w->name[w->pwall[0]], w->where[0]);
  for (PetscInt p = 1; p < w->npoly; p++) {
    PetscCheck(w->area[p] < 0, comm, PETSC_ERR_ARG_WRONG,
               "Inconsistent normals: obstacle polygon %" PetscInt_FMT
               " of wall \"%s\" (%s) runs counter-clockwise; obstacles inside the container must run clockwise (liquid "
               "outside them)",
               p, w->name[w->pwall[p]], w->where[p]);
    for (PetscInt v = w->pstart[p]; v < w->pstart[p + 1]; v++)
      PetscCheck(InPolygon(w, 0, &w->vert[2 * v]), comm, PETSC_ERR_ARG_WRONG,
                 "Vertex (%g, %g) of obstacle polygon %" PetscInt_FMT
                 " (wall \"%s\", %s) lies outside the container (%s)",
                 (double)w->vert[2 * v], (double)w->vert[2 * v + 1], p, w->name[w->pwall[p]], w->where[p], w->where[0]);
  }
  for (PetscInt p = 0; p < w->npoly; p++)
    for (PetscInt q = p + 1; q < w->npoly; q++)
      for (PetscInt i = w->pstart[p]; i < w->pstart[p + 1]; i++) {
        const PetscInt i1 = i + 1 < w->pstart[p + 1] ? i + 1 : w->pstart[p];
        for (PetscInt j = w->pstart[q]; j < w->pstart[q + 1]; j++) {
          const PetscInt j1 = j + 1 < w->pstart[q + 1] ? j + 1 : w->pstart[q];
          PetscCheck(!SegmentsIntersect(&w->vert[2 * i], &w->vert[2 * i1], &w->vert[2 * j], &w->vert[2 * j1]), comm,
                     PETSC_ERR_ARG_WRONG,
                     "Polygons %" PetscInt_FMT " (wall \"%s\", %s) and %" PetscInt_FMT
                     " (wall \"%s\", %s) meet: walls must not touch or cross (make a baffle that touches the tank part "
                     "of the tank's outline)",
                     p, w->name[w->pwall[p]], w->where[p], q, w->name[w->pwall[q]], w->where[q]);
        }
      }
  w->lo[0] = w->lo[1] = PETSC_MAX_REAL;
  w->hi[0] = w->hi[1] = -PETSC_MAX_REAL;
  for (PetscInt v = 0; v < w->nvert; v++)
    for (PetscInt d = 0; d < 2; d++) {
      w->lo[d] = PetscMin(w->lo[d], w->vert[2 * v + d]);
      w->hi[d] = PetscMax(w->hi[d], w->vert[2 * v + d]);
    }
  PetscFunctionReturn(0);
}

/* FSWallsRectangularTank - a closed rectangular tank [0, L] x [0, H], wall "tank". */
PetscErrorCode FSWallsRectangularTank(FSWalls *w, MPI_Comm comm, PetscReal L, PetscReal H)
{
  const PetscReal xy[8] = {0, 0, L, 0, L, H, 0, H};

  PetscFunctionBegin;
  PetscCheck(L > 0 && H > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Tank length %g and height %g must be positive", (double)L,
             (double)H);
  PetscCall(FSWallsAddPolygon(w, comm, "tank", 4, xy, "rectangular tank"));
  PetscFunctionReturn(0);
}

/*
   FSWallsBaffledTank - a tank of ncomp compartments of length Lc separated by ncomp-1 vertical
   baffles of the given thickness (overall length ncomp Lc + (ncomp-1) thickness, height H). Each
   baffle spans [bottom_gap, bottom_gap + baffle_height] vertically. A baffle from the bottom
   (bottom_gap = 0) or up to the lid is part of the tank's outline (wall "tank"); a free-standing one
   is an obstacle polygon of wall "baffles". Seed: 7 compartments of 0.1 m, 5 mm baffles, 0.73 m.
*/
PetscErrorCode FSWallsBaffledTank(FSWalls *w, MPI_Comm comm, PetscInt ncomp, PetscReal Lc, PetscReal t, PetscReal H,
                                  PetscReal gap, PetscReal hb)
{
  const PetscReal L = ncomp * Lc + (ncomp - 1) * t, top = gap + hb;
  PetscReal      *xy;
  PetscInt        n          = 0;
  const PetscBool frombottom = (PetscBool)(gap <= 0), tolid = (PetscBool)(top >= H);

  PetscFunctionBegin;
  PetscCheck(ncomp >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE, "Number of compartments %" PetscInt_FMT " must be at least 1",
             ncomp);
  PetscCheck(Lc > 0 && H > 0 && t > 0, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Compartment length %g, baffle thickness %g and tank height %g must be positive", (double)Lc, (double)t,
             (double)H);
  PetscCheck(gap >= 0 && hb > 0 && top <= H, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Baffle from %g to %g does not fit in the tank height %g", (double)gap, (double)top, (double)H);
  PetscCheck(!(frombottom && tolid), comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Baffles spanning the whole height %g would close the compartments: leave an opening (bottom gap or lower "
             "height)",
             (double)H);
  PetscCall(PetscMalloc1(2 * (8 + 8 * ncomp), &xy));
#define PUSH(X, Y) (xy[2 * n] = (X), xy[2 * n + 1] = (Y), n++)
  /* the outline, counter-clockwise from the origin: bottom left to right, then the lid right to left */
  PUSH(0, 0);
  for (PetscInt b = 1; b < ncomp && frombottom; b++) {
    const PetscReal x0 = b * Lc + (b - 1) * t;
    PUSH(x0, 0);
    PUSH(x0, top);
    PUSH(x0 + t, top);
    PUSH(x0 + t, 0);
  }
  PUSH(L, 0);
  PUSH(L, H);
  for (PetscInt b = ncomp - 1; b >= 1 && tolid; b--) {
    const PetscReal x0 = b * Lc + (b - 1) * t;
    PUSH(x0 + t, H);
    PUSH(x0 + t, gap);
    PUSH(x0, gap);
    PUSH(x0, H);
  }
  PUSH(0, H);
  PetscCall(FSWallsAddPolygon(w, comm, "tank", n, xy, "baffled tank"));
  if (!frombottom && !tolid)
    for (PetscInt b = 1; b < ncomp; b++) {
      const PetscReal x0   = b * Lc + (b - 1) * t;
      const PetscReal r[8] = {x0, gap, x0, top, x0 + t, top, x0 + t, gap}; /* clockwise */
      PetscCall(FSWallsAddPolygon(w, comm, "baffles", 4, r, "baffled tank"));
    }
#undef PUSH
  PetscCall(PetscFree(xy));
  PetscFunctionReturn(0);
}

/*
   FSWallsLoad - reads walls from a text file (rank 0 reads, all ranks get the result):

     # comment (anywhere after #)
     wall <name>        start a polygon of the wall <name>
     <x> <y> [<edge>]   one vertex per line; the edge from it to the next vertex belongs to the wall
                        <edge> if given (a floor that is no-slip, the load on one side), else to <name>
     end                close the polygon (the last vertex connects to the first)

   The first polygon is the container (counter-clockwise); later ones are obstacles (clockwise).
   Errors name the file and line.
*/
PetscErrorCode FSWallsLoad(FSWalls *w, MPI_Comm comm, const char path[])
{
  FILE      *fp   = NULL;
  char      *text = NULL, *next, name[64] = "", where[FS_WALLS_WHERE_LEN];
  size_t     size = 0;
  PetscReal *xy   = NULL;
  char(*edge)[64] = NULL; /* the wall of each edge, "" for the polygon's */
  PetscInt    n = 0, cap = 0, lineno = 0, start = 0, npoly0 = w->npoly;
  PetscBool   open = PETSC_FALSE;
  const char *why;

  PetscFunctionBegin;
  /* every rank reads and parses the (small) file, so that every rank raises the same error */
  {
    PetscBool elsewhere;
    PetscCall(FSFileOpenOnEveryRank(comm, path, "r", &fp, &elsewhere, &why));
    PetscCheck(fp, comm, PETSC_ERR_FILE_OPEN, "Cannot open the wall file \"%s\"%s%s", path,
               elsewhere ? " on some of the other ranks" : ": ", elsewhere ? "" : why);
  }
  PetscCall(FSFileReadAll(fp, &text, &size)); /* the whole file, which may hold NUL bytes */
  {
    const char *bom = FSTextByteOrderMark(text, size);
    if (bom) PetscCall(PetscFree(text));
    PetscCheck(!bom, comm, PETSC_ERR_FILE_UNEXPECTED,
               "%s:1: the file starts with %s: save it as plain text, ASCII or UTF-8 without the mark (docs/walls.md)",
               path, bom);
  }
  for (char *line = text; line; line = next) {
    char       *c, *tok[4], *save = NULL, shown[96];
    const char *bad;
    int         ntok = 0;
    next             = memchr(line, '\n', (size_t)(text + size - line));
    if (next) *next++ = 0;
    lineno++;
    PetscCheck((size_t)((next ? next - 1 : text + size) - line) == strlen(line), comm, PETSC_ERR_FILE_UNEXPECTED,
               "%s:%" PetscInt_FMT ": a NUL byte: a wall file is text (docs/walls.md)", path, lineno);
    if ((c = strchr(line, '#'))) *c = 0;
    PetscCall(PetscStrncpy(shown, line, sizeof(shown))); /* for the messages: strtok_r cuts the line */
    for (char *t = strtok_r(line, " \t\r\f\v", &save); t; t = strtok_r(NULL, " \t\r\f\v", &save)) {
      PetscCheck(ntok < 3, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": cannot parse \"%s\": too many words; expected two numbers x y (and the name of "
                 "the edge's wall), \"wall <name>\" or \"end\"",
                 path, lineno, shown);
      tok[ntok++] = t;
    }
    if (!ntok) continue;
    if (!strcmp(tok[0], "wall")) {
      PetscCheck(!open, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": \"wall\" before the \"end\" of wall \"%s\" (started on line %" PetscInt_FMT ")",
                 path, lineno, name, start);
      PetscCheck(ntok == 2, comm, PETSC_ERR_FILE_UNEXPECTED, "%s:%" PetscInt_FMT ": expected \"wall <name>\"%s", path,
                 lineno, ntok == 1 ? ": \"wall\" needs a name" : ", found more words");
      bad = FSWallNameProblem(tok[1]);
      PetscCheck(!bad, comm, PETSC_ERR_FILE_UNEXPECTED, "%s:%" PetscInt_FMT ": bad wall name \"%.80s\": %s", path,
                 lineno, tok[1], bad);
      PetscCall(PetscStrncpy(name, tok[1], sizeof(name)));
      open  = PETSC_TRUE;
      n     = 0;
      start = lineno;
    } else if (!strcmp(tok[0], "end")) {
      PetscCheck(open, comm, PETSC_ERR_FILE_UNEXPECTED, "%s:%" PetscInt_FMT ": \"end\" without \"wall\"", path, lineno);
      PetscCheck(ntok == 1, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": expected \"end\" alone, found \"%s\"", path, lineno, tok[1]);
      PetscCall(PetscSNPrintf(where, sizeof(where), "%s:%" PetscInt_FMT "-%" PetscInt_FMT, path, start, lineno));
      PetscCall(FSWallsAddPolygon(w, comm, name, n, xy, where));
      for (PetscInt k = 0, p = w->npoly - 1; k < w->pstart[p + 1] - w->pstart[p]; k++)
        if (edge[k][0]) PetscCall(FSWallsSetEdgeWall(w, comm, p, k, edge[k]));
      open = PETSC_FALSE;
    } else {
      double v[2];
      PetscCheck(open, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": \"%.80s\" outside \"wall <name>\" ... \"end\": expected \"wall <name>\"", path,
                 lineno, tok[0]);
      for (int d = 0; d < 2; d++) {
        char *e = NULL;
        v[d]    = d < ntok ? strtod(tok[d], &e) : 0;
        PetscCheck(d < ntok && e != tok[d] && !*e, comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT
                   ": cannot parse \"%s\": %s%.80s%s; expected two numbers x y (and the name of the "
                   "edge's wall), \"wall <name>\" or \"end\"",
                   path, lineno, shown, d < ntok ? "\"" : "", d < ntok ? tok[d] : "no y coordinate",
                   d < ntok ? "\" is not a number" : "");
        PetscCheck(!PetscIsInfOrNanReal((PetscReal)v[d]), comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT ": %c = \"%s\" is not a finite number", path, lineno, d ? 'y' : 'x', tok[d]);
      }
      if (ntok == 3) {
        bad = FSWallNameProblem(tok[2]);
        PetscCheck(!bad, comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT ": bad wall name \"%.80s\" of the edge: %s", path, lineno, tok[2], bad);
      }
      if (n == cap) {
        PetscReal *nxy;
        char(*nedge)[64];
        cap = PetscMax(64, 2 * cap);
        PetscCall(PetscMalloc1(2 * cap, &nxy));
        PetscCall(PetscMalloc1(cap, &nedge));
        if (n) {
          PetscCall(PetscArraycpy(nxy, xy, 2 * n));
          PetscCall(PetscArraycpy(nedge, edge, n));
        }
        PetscCall(PetscFree(xy));
        PetscCall(PetscFree(edge));
        xy   = nxy;
        edge = nedge;
      }
      xy[2 * n]     = v[0];
      xy[2 * n + 1] = v[1];
      PetscCall(PetscStrncpy(edge[n], ntok == 3 ? tok[2] : "", sizeof(edge[n])));
      n++;
    }
  }
  PetscCall(PetscFree(text));
  PetscCheck(!open, comm, PETSC_ERR_FILE_UNEXPECTED,
             "%s: wall \"%s\" (line %" PetscInt_FMT ") has no \"end\": the polygon is open", path, name, start);
  PetscCheck(w->npoly > npoly0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "%s: no wall in the file: expected \"wall <name>\", a vertex \"x y\" a line, \"end\" (docs/walls.md)",
             path);
  PetscCall(PetscFree(xy));
  PetscCall(PetscFree(edge));
  PetscFunctionReturn(0);
}

/* FSWallsDiscretize - splits every edge into segments of length at most dx (about dx). */
PetscErrorCode FSWallsDiscretize(FSWalls *w, PetscReal dx)
{
  PetscInt nseg  = 0;
  double   count = 0, mem = FSMemoryTotal();

  PetscFunctionBegin;
  w->dx = dx;
  for (PetscInt p = 0; p < w->npoly; p++)
    for (PetscInt v = w->pstart[p]; v < w->pstart[p + 1]; v++) {
      const PetscInt  v1 = v + 1 < w->pstart[p + 1] ? v + 1 : w->pstart[p];
      const PetscReal L  = PetscSqrtReal(PetscSqr(w->vert[2 * v1] - w->vert[2 * v]) +
                                         PetscSqr(w->vert[2 * v1 + 1] - w->vert[2 * v + 1]));
      count += PetscCeilReal(L / dx - 1e-9);
    }
  /* every rank holds every segment: a count past the integers or the memory (walls in millimetres read as
     metres, a huge coordinate) stops here, before the arrays are allocated */
  PetscCheck(count < PETSC_MAX_INT / FS_SEG_STRIDE &&
                 (!mem || count * (FS_SEG_STRIDE * sizeof(PetscReal) + sizeof(PetscInt)) < mem),
             PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "The walls (%s, bounding box [%g, %g] x [%g, %g]) at dx %g make %.3g segments, more than %s: check the "
             "coordinates (in metres) and -fs_dx",
             w->npoly ? w->where[0] : "none", (double)w->lo[0], (double)w->hi[0], (double)w->lo[1], (double)w->hi[1],
             (double)dx, count,
             count < PETSC_MAX_INT / FS_SEG_STRIDE ? "this machine's memory holds" : "an index can count");
  nseg = (PetscInt)count;
  PetscCall(PetscFree(w->seg));
  PetscCall(PetscFree(w->segwall));
  PetscCall(PetscMalloc1(nseg * FS_SEG_STRIDE, &w->seg));
  PetscCall(PetscMalloc1(nseg, &w->segwall));
  w->nseg = 0;
  for (PetscInt p = 0; p < w->npoly; p++)
    for (PetscInt v = w->pstart[p]; v < w->pstart[p + 1]; v++) {
      const PetscInt   v1 = v + 1 < w->pstart[p + 1] ? v + 1 : w->pstart[p];
      const PetscReal *a = &w->vert[2 * v], *b = &w->vert[2 * v1];
      const PetscReal  L = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]));
      const PetscInt   m = (PetscInt)PetscCeilReal(L / dx - 1e-9);
      for (PetscInt k = 0; k < m; k++) {
        PetscReal *s          = &w->seg[w->nseg * FS_SEG_STRIDE];
        s[FS_SEG_P0]          = a[0] + (b[0] - a[0]) * k / m;
        s[FS_SEG_P0 + 1]      = a[1] + (b[1] - a[1]) * k / m;
        s[FS_SEG_P1]          = a[0] + (b[0] - a[0]) * (k + 1) / m;
        s[FS_SEG_P1 + 1]      = a[1] + (b[1] - a[1]) * (k + 1) / m;
        s[FS_SEG_MID]         = 0.5 * (s[FS_SEG_P0] + s[FS_SEG_P1]);
        s[FS_SEG_MID + 1]     = 0.5 * (s[FS_SEG_P0 + 1] + s[FS_SEG_P1 + 1]);
        s[FS_SEG_NORMAL]      = (b[1] - a[1]) / L;
        s[FS_SEG_NORMAL + 1]  = -(b[0] - a[0]) / L;
        s[FS_SEG_LENGTH]      = L / m;
        w->segwall[w->nseg++] = w->vwall[v];
      }
    }
  PetscFunctionReturn(0);
}

/* Distance from x to the nearest wall segment (after FSWallsDiscretize). */
PetscReal FSWallsDistance(const FSWalls *w, const PetscReal x[])
{
  PetscReal best = PETSC_MAX_REAL;
  for (PetscInt k = 0; k < w->nseg; k++) best = PetscMin(best, FSSegmentDistance2(&w->seg[k * FS_SEG_STRIDE], x));
  return PetscSqrtReal(best);
}

/* Is x in the liquid region (inside the container, outside every obstacle) and at least margin from the walls? */
PetscBool FSWallsInLiquid(const FSWalls *w, const PetscReal x[], PetscReal margin)
{
  if (!InPolygon(w, 0, x)) return PETSC_FALSE;
  for (PetscInt p = 1; p < w->npoly; p++)
    if (InPolygon(w, p, x)) return PETSC_FALSE;
  return (PetscBool)(margin <= 0 || FSWallsDistance(w, x) >= margin);
}

/*
   FSWallsLiquidBelow - the area of the liquid region of w (inside the container, outside the obstacles) in the
   strip x0 <= x <= x1 below the level t, and its moment about the level, the integral of t - y over it: exact for
   any polygons.

   Not collective

   Notes:
   The divergence theorem with F = (0, y - t) (div F = 1) for the area and F = (0, -(y - t)^2 / 2) (div F = t - y)
   for the moment: F vanishes on the line y = t and F . n on the strip's sides, so both are integrals over the
   walls' edges clipped to the strip below t alone, the normal n pointing out of the liquid (for the edge p0 -> p1,
   n ds = (dy, -dx): n_y ds = -dx).
*/
void FSWallsLiquidBelow(const FSWalls *w, PetscReal x0, PetscReal x1, PetscReal t, PetscReal *area, PetscReal *moment)
{
  *area   = 0;
  *moment = 0;
  for (PetscInt q = 0; q < w->npoly; q++)
    for (PetscInt e = w->pstart[q]; e < w->pstart[q + 1]; e++) {
      const PetscInt   f = e + 1 < w->pstart[q + 1] ? e + 1 : w->pstart[q];
      const PetscReal *p = &w->vert[2 * e], d[2] = {w->vert[2 * f] - p[0], w->vert[2 * f + 1] - p[1]};
      /* the edge p + s d, s in [s0, s1], clipped to x >= x0, x <= x1 and y <= t (Liang-Barsky) */
      const PetscReal dir[3] = {-d[0], d[0], d[1]}, room[3] = {p[0] - x0, x1 - p[0], t - p[1]};
      PetscReal       s0 = 0, s1 = 1, a, b, dxe;
      for (PetscInt k = 0; k < 3 && s0 < s1; k++) {
        if (dir[k] == 0) {
          if (room[k] < 0) s1 = s0;
        } else if (dir[k] > 0) s1 = PetscMin(s1, room[k] / dir[k]);
        else s0 = PetscMax(s0, room[k] / dir[k]);
      }
      if (s0 >= s1) continue;
      a   = p[1] + s0 * d[1] - t; /* y - t at the clipped ends */
      b   = p[1] + s1 * d[1] - t;
      dxe = (s1 - s0) * d[0];
      *area -= dxe * 0.5 * (a + b);
      *moment += 0.5 * dxe * (a * a + a * b + b * b) / 3;
    }
}
