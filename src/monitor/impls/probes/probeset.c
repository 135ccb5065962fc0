/*
   The probe set of the probes monitor (-fs_probes FILE, -fs_probe_interval N): the pressure and velocity of the
   liquid at points, and the free-surface elevation along lines, every N steps into probes.csv (probes.c) and
   through FSSolverGetProbes(); the solver's data come through FSSolverGetParticleView(). docs/running.md, "Probes
   and wave gauges", has the file format and the interpolation.

   Each sample evaluates the right-hand side once at the current state (as the snapshots' pressure
   does), so that the particles' volumes and pressures, the body field of the tank's frame and the wall
   pressure are those of the state sampled, not of the step's last stage. A probe on a wall reads the wall
   pressure averaged over its face, and a probe with a cut-off or a rate adds its sensor's reading, the raw
   pressure through the sensor's time response (sensor.c).
*/
#include "monitor/impls/probes/probesimpl.h"
#include <ctype.h>
#include <sys/stat.h>

/* The probe file's text, read on rank 0 and broadcast (every rank parses the same text, so that every
   rank raises the same error). */
static PetscErrorCode FSProbesReadFile(MPI_Comm comm, const char path[], char **text)
{
  PetscMPIInt rank;
  long        len = 0;
  char       *buf = NULL;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    FILE       *fp = fopen(path, "rb");
    struct stat sb;
    if (!fp) len = -1;
    else if (fstat(fileno(fp), &sb) != 0 || !S_ISREG(sb.st_mode)) { /* a directory opens, and seeks to a huge size */
      len = -2;
      fclose(fp);
    } else {
      size_t size;
      PetscCall(FSFileReadAll(fp, &buf, &size));
      len = (long)size;
    }
  }
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_LONG, 0, comm));
  PetscCheck(len >= 0, comm, PETSC_ERR_FILE_OPEN, "Cannot read the probe file \"%s\" (-fs_probes)%s", path,
             len == -2 ? ": not a regular file" : "");
  if (rank) PetscCall(PetscMalloc1(len + 1, &buf));
  PetscCallMPI(MPI_Bcast(buf, (PetscMPIInt)len, MPI_CHAR, 0, comm));
  buf[len] = 0;
  if (strlen(buf) < (size_t)len) { /* the parser would stop there, leaving the rest unread */
    PetscInt line = 1;
    for (const char *c = buf; *c; c++) line += (*c == '\n');
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "%s:%" PetscInt_FMT ": a NUL byte: a probe file (-fs_probes) is text",
            path, line);
  }
  {
    const char *bom = FSTextByteOrderMark(buf, (size_t)len);
    if (bom) PetscCall(PetscFree(buf));
    PetscCheck(!bom, comm, PETSC_ERR_FILE_UNEXPECTED,
               "%s:1: the file starts with %s: save it as plain text, ASCII or UTF-8 without the mark (-fs_probes)",
               path, bom);
  }
  *text = buf;
  PetscFunctionReturn(0);
}

/* a number of the probe file, or PETSC_FALSE */
static PetscBool FSProbesNumber(const char *tok, PetscReal *v)
{
  char  *end;
  double d;
  if (!tok) return PETSC_FALSE;
  d = strtod(tok, &end);
  if (end == tok || *end || PetscIsInfOrNanReal((PetscReal)d)) return PETSC_FALSE;
  *v = (PetscReal)d;
  return PETSC_TRUE;
}

/* Parses the probe file's text into the set's items, checking each line. */
static PetscErrorCode FSProbesParse(FSProbeSet *ps, const FSSolverParticleView *pv, MPI_Comm comm, char *text)
{
  const PetscInt           dim    = pv->dim;
  const char              *path   = ps->file;
  PetscInt                 lineno = 0, cap = 0;
  char                    *line, *next     = text;
  const PetscReal          span = PetscMax(pv->hi[0] - pv->lo[0], pv->hi[1] - pv->lo[1]), tol = 1e-9 * span;
  static const char *const axis[] = {"x", "y", "z"};

  PetscFunctionBegin;
  for (char *c = text; *c; c++) cap += (*c == '\n');
  PetscCall(PetscCalloc1(cap + 1, &ps->item));
  ps->n = 0;
  while (next) { /* line by line (strtok would skip empty lines and miscount) */
    char    *tok[16], *hash, *tsave = NULL;
    PetscInt ntok = 0;
    FSProbe *it   = &ps->item[ps->n];
    line          = next;
    next          = strchr(line, '\n');
    if (next) *next++ = 0;
    lineno++;
    if ((hash = strchr(line, '#'))) *hash = 0;
    for (char *t = strtok_r(line, " \t\r\f\v", &tsave); t; t = strtok_r(NULL, " \t\r\f\v", &tsave)) {
      PetscCheck(ntok < 16, comm, PETSC_ERR_FILE_UNEXPECTED, "%s:%" PetscInt_FMT ": too many values", path, lineno);
      tok[ntok++] = t;
    }
    if (!ntok) continue;
    PetscCheck(!strcmp(tok[0], "probe") || !strcmp(tok[0], "gauge"), comm, PETSC_ERR_FILE_UNEXPECTED,
               "%s:%" PetscInt_FMT
               ": unknown item \"%s\": expected \"probe NAME x y%s [diameter D] ...\" or \"gauge NAME "
               "x0 y0%s x1 y1%s\"",
               path, lineno, tok[0], dim == 3 ? " z" : "", dim == 3 ? " z0" : "", dim == 3 ? " z1" : "");
    it->gauge = (PetscBool)!strcmp(tok[0], "gauge");
    PetscCheck(ntok >= 2, comm, PETSC_ERR_FILE_UNEXPECTED, "%s:%" PetscInt_FMT ": \"%s\" needs a name", path, lineno,
               tok[0]);
    {
      PetscBool ok = (PetscBool)(strlen(tok[1]) < FS_PROBE_NAME_LEN && !strpbrk(tok[1], ",\"") &&
                                 ((tok[1][0] >= 'a' && tok[1][0] <= 'z') || (tok[1][0] >= 'A' && tok[1][0] <= 'Z')));
      for (const char *c = tok[1]; ok && *c; c++) ok = (PetscBool)(*c > 0x20 && *c < 0x7f); /* it names CSV columns */
      PetscCheck(ok, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT
                 ": bad name \"%.80s\": a name starts with a letter, has printable ASCII characters, no "
                 "comma or quote, and fewer than %d characters",
                 path, lineno, tok[1], FS_PROBE_NAME_LEN);
    }
    for (PetscInt k = 0; k < ps->n; k++)
      PetscCheck(strcmp(ps->item[k].name, tok[1]), comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": duplicate name \"%s\": every probe and gauge needs its own", path, lineno,
                 tok[1]);
    PetscCall(PetscStrncpy(it->name, tok[1], sizeof(it->name)));
    it->line = lineno;
    if (!it->gauge) { /* the point, then the sensor's keywords, each once, in any order */
      PetscBool ok = (PetscBool)(ntok >= 2 + dim);
      for (PetscInt d = 0; ok && d < dim; d++) ok = FSProbesNumber(tok[2 + d], &it->x0[d]);
      PetscCheck(ok, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": probe \"%s\": expected \"probe NAME x y%s [diameter D] [cutoff HZ] [order 1|2] "
                 "[rate HZ]\" (%" PetscInt_FMT " coordinates)",
                 path, lineno, it->name, dim == 3 ? " z" : "", dim);
      it->order = 1;
      for (PetscInt q = 2 + dim; q < ntok; q += 2) {
        static const char *key[]  = {"diameter", "cutoff", "order", "rate"};
        static const char *what[] = {"a positive diameter D (m)", "a positive cut-off frequency (Hz)", "1 or 2",
                                     "a positive sampling rate (Hz)"};
        PetscReal         *dest[] = {&it->diameter, &it->cutoff, NULL, &it->rate}, v = 0;
        PetscInt           k = 0;
        while (k < 4 && strcmp(tok[q], key[k])) k++;
        PetscCheck(
            k < 4 || !FSProbesNumber(tok[q], &v), comm, PETSC_ERR_FILE_UNEXPECTED,
            "%s:%" PetscInt_FMT ": probe \"%s\": expected \"probe NAME x y%s [diameter D] [cutoff HZ] [order 1|2] "
            "[rate HZ]\": a %" PetscInt_FMT "-D probe has %" PetscInt_FMT " coordinates, then keywords; \"%s\" is "
            "a number where a keyword belongs",
            path, lineno, it->name, dim == 3 ? " z" : "", dim, dim, tok[q]);
        PetscCheck(k < 4, comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT
                   ": probe \"%s\": unknown keyword \"%s\": expected diameter, cutoff, order or rate",
                   path, lineno, it->name, tok[q]);
        for (PetscInt r = 2 + dim; r < q; r += 2)
          PetscCheck(strcmp(tok[r], tok[q]), comm, PETSC_ERR_FILE_UNEXPECTED,
                     "%s:%" PetscInt_FMT ": probe \"%s\": \"%s\" given twice", path, lineno, it->name, tok[q]);
        ok = (PetscBool)(q + 1 < ntok && FSProbesNumber(tok[q + 1], &v) && v > 0);
        if (ok && k == 2) ok = (PetscBool)(v == 1 || v == 2);
        PetscCheck(ok, comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT ": probe \"%s\": \"%s\" needs %s, got \"%s\"", path, lineno, it->name, key[k],
                   what[k], q + 1 < ntok ? tok[q + 1] : "nothing");
        if (dest[k]) *dest[k] = v;
        else it->order = (PetscInt)v;
      }
      it->filtered     = (PetscBool)(it->cutoff > 0 || it->rate > 0);
      it->filter.order = it->order;
      it->filter.omega = 2 * PETSC_PI * it->cutoff;
      it->filter.rate  = it->rate;
      for (PetscInt d = 0; d < dim; d++)
        PetscCheck(it->x0[d] >= pv->lo[d] - tol && it->x0[d] <= pv->hi[d] + tol, comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT ": probe \"%s\" is outside the domain: its %s = %g is not in [%g, %g]", path,
                   lineno, it->name, axis[d], (double)it->x0[d], (double)pv->lo[d], (double)pv->hi[d]);
    } else {
      PetscBool ok = (PetscBool)(ntok == 2 + 2 * dim);
      PetscReal L2 = 0;
      for (PetscInt d = 0; ok && d < dim; d++)
        ok = (PetscBool)(FSProbesNumber(tok[2 + d], &it->x0[d]) && FSProbesNumber(tok[2 + dim + d], &it->x1[d]));
      PetscCheck(ok, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": gauge \"%s\": expected \"gauge NAME x0 y0%s x1 y1%s\" (%" PetscInt_FMT
                 " numbers: the line's start, then its end)",
                 path, lineno, it->name, dim == 3 ? " z0" : "", dim == 3 ? " z1" : "", 2 * dim);
      for (PetscInt d = 0; d < dim; d++) /* a gauge samples every dx/4 along its length: no further than the domain */
        PetscCheck(it->x0[d] >= pv->lo[d] - tol && it->x0[d] <= pv->hi[d] + tol && it->x1[d] >= pv->lo[d] - tol &&
                       it->x1[d] <= pv->hi[d] + tol,
                   comm, PETSC_ERR_FILE_UNEXPECTED,
                   "%s:%" PetscInt_FMT ": gauge \"%s\" reaches outside the domain: the %s of its ends, %g and %g, is "
                   "not in [%g, %g]",
                   path, lineno, it->name, axis[d], (double)it->x0[d], (double)it->x1[d], (double)pv->lo[d],
                   (double)pv->hi[d]);
      for (PetscInt d = 0; d < dim; d++) L2 += PetscSqr(it->x1[d] - it->x0[d]);
      PetscCheck(PetscSqrtReal(L2) > tol, comm, PETSC_ERR_FILE_UNEXPECTED,
                 "%s:%" PetscInt_FMT ": gauge \"%s\" has zero length: its two ends are the same point", path, lineno,
                 it->name);
    }
    ps->n++;
  }
  PetscFunctionReturn(0);
}

/* the distance from x to a wall element's plane (line in 2-D), and whether x lies within the element's
   extent along it (its half length in 2-D, the radius of a disc of twice its area in 3-D, plus tol) */
static void FSProbesElementDistance(const FSWallView *B, PetscInt e, const PetscReal x[], PetscReal tol, PetscReal *dn,
                                    PetscBool *over, PetscReal *lateral)
{
  const PetscReal *row = &B->element[e * B->stride], *c = row + B->centroid, *nrm = row + B->normal;
  const PetscReal  ext = B->dim == 2 ? 0.5 * row[B->measure] : PetscSqrtReal(2 * row[B->measure] / PETSC_PI);
  PetscReal        d = 0, r2 = 0;
  for (PetscInt a = 0; a < B->dim; a++) d += (x[a] - c[a]) * nrm[a];
  for (PetscInt a = 0; a < B->dim; a++) r2 += PetscSqr(x[a] - c[a] - d * nrm[a]);
  *dn   = PetscAbsReal(d);
  *over = (PetscBool)(PetscSqrtReal(r2) <= ext + tol);
  if (lateral) *lateral = PetscSqrtReal(r2);
}

/* appends element e with weight w to the probes' element list, growing it */
static PetscErrorCode FSProbesAddElement(FSProbeSet *ps, PetscInt *cap, PetscInt e, PetscReal w)
{
  PetscFunctionBegin;
  if (ps->nelem == *cap) {
    PetscInt  *elem;
    PetscReal *ewt;
    *cap = PetscMax(16, 2 * *cap);
    PetscCall(PetscMalloc2(*cap, &elem, *cap, &ewt));
    PetscCall(PetscArraycpy(elem, ps->elem, ps->nelem));
    PetscCall(PetscArraycpy(ewt, ps->ewt, ps->nelem));
    PetscCall(PetscFree2(ps->elem, ps->ewt));
    ps->elem = elem;
    ps->ewt  = ewt;
  }
  ps->elem[ps->nelem]  = e;
  ps->ewt[ps->nelem++] = w;
  PetscFunctionReturn(0);
}

/* the elements of a wall probe's face: the segment (2-D) or disc (3-D) of diameter D centred at the probe's point
   in the plane of its nearest element. An element facing the same way (normals within 60 degrees) and whose centroid
   is within dx/2 + D/4 of that plane (a curved wall's elements near the face) is projected on the plane; its weight
   is its area times the share of its projection inside the face (sensor.c), exact on a plane wall. */
static PetscErrorCode FSProbesFace(const FSWallView *B, const FSProbe *it, PetscInt near, PetscReal dx, FSProbeSet *ps,
                                   PetscInt *cap)
{
  const PetscInt   dim = B->dim;
  const PetscReal *ns = &B->element[near * B->stride + B->normal], R = 0.5 * it->diameter;
  PetscReal        e1[3] = {0, 0, 0}, e2[3] = {0, 0, 0};

  PetscFunctionBegin;
  if (dim == 2) {
    e1[0] = -ns[1];
    e1[1] = ns[0];
  } else { /* an orthonormal basis of the plane */
    const PetscInt ax = PetscAbsReal(ns[0]) < PetscAbsReal(ns[1]) ? (PetscAbsReal(ns[0]) < PetscAbsReal(ns[2]) ? 0 : 2)
                                                                  : (PetscAbsReal(ns[1]) < PetscAbsReal(ns[2]) ? 1 : 2);
    PetscReal      a[3] = {0, 0, 0}, l;
    a[ax]               = 1;
    e1[0]               = ns[1] * a[2] - ns[2] * a[1];
    e1[1]               = ns[2] * a[0] - ns[0] * a[2];
    e1[2]               = ns[0] * a[1] - ns[1] * a[0];
    l                   = PetscSqrtReal(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (PetscInt d = 0; d < 3; d++) e1[d] /= l;
    e2[0] = ns[1] * e1[2] - ns[2] * e1[1];
    e2[1] = ns[2] * e1[0] - ns[0] * e1[2];
    e2[2] = ns[0] * e1[1] - ns[1] * e1[0];
  }
  for (PetscInt e = 0; e < B->nelements; e++) {
    const PetscReal *row = &B->element[e * B->stride], *c = row + B->centroid, *ne = row + B->normal,
                    *v = row + B->vertex, A = row[B->measure];
    PetscReal cosn = 0, off = 0, w = 0;
    for (PetscInt d = 0; d < dim; d++) {
      cosn += ne[d] * ns[d];
      off += (c[d] - it->x0[d]) * ns[d];
    }
    if (cosn < 0.5 || PetscAbsReal(off) > 0.5 * dx + 0.5 * R) continue;
    if (dim == 2) {
      PetscReal sa = 0, sb = 0;
      for (PetscInt d = 0; d < 2; d++) {
        sa += (v[d] - it->x0[d]) * e1[d];
        sb += (v[2 + d] - it->x0[d]) * e1[d];
      }
      if (PetscAbsReal(sb - sa) > 0) w = A * FSSensorSegmentOverlap(sa, sb, R) / PetscAbsReal(sb - sa);
    } else {
      PetscReal p[3][2], Ap;
      for (PetscInt q = 0; q < 3; q++) {
        p[q][0] = p[q][1] = 0;
        for (PetscInt d = 0; d < 3; d++) {
          p[q][0] += (v[3 * q + d] - it->x0[d]) * e1[d];
          p[q][1] += (v[3 * q + d] - it->x0[d]) * e2[d];
        }
      }
      Ap = 0.5 * PetscAbsReal((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
      if (Ap > 0) w = A * FSSensorDiscTriangleArea(R, p) / Ap;
    }
    if (w > 1e-12 * A) PetscCall(FSProbesAddElement(ps, cap, e, w));
  }
  PetscFunctionReturn(0);
}

/* a point of item it (a probe's point, a gauge's end) must lie in the liquid region, where its readings mean
   something: inside the container's closed walls and outside every wall's solid (FSBoundaryLocate), or on a wall
   (onwall: a probe within dx/2 of a wall element; a gauge's end within dx/2 of a wall). Otherwise an error naming the
   file, the line, the item and the nearest wall. */
static PetscErrorCode FSProbesCheckInLiquid(const FSProbeSet *ps, const FSSolverParticleView *pv, MPI_Comm comm,
                                            const FSProbe *it, const PetscReal x[], PetscBool onwall, const char what[])
{
  PetscBool          in;
  PetscInt           wall, nwalls;
  PetscReal          dist, lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  const char *const *names;
  PetscBool          inbox = PETSC_TRUE;
  char               at[128];

  PetscFunctionBegin;
  PetscCall(FSBoundaryLocate(pv->boundary, x, &in, &wall, &dist));
  if (in || onwall || (it->gauge && dist <= 0.5 * pv->dx)) PetscFunctionReturn(0);
  PetscCall(FSBoundaryGetWallNames(pv->boundary, &nwalls, &names));
  PetscCall(FSBoundaryGetBoundingBox(pv->boundary, lo, hi));
  for (PetscInt d = 0; d < pv->dim; d++) inbox = (PetscBool)(inbox && x[d] >= lo[d] && x[d] <= hi[d]);
  if (pv->dim == 3) PetscCall(PetscSNPrintf(at, sizeof(at), "(%g, %g, %g)", (double)x[0], (double)x[1], (double)x[2]));
  else PetscCall(PetscSNPrintf(at, sizeof(at), "(%g, %g)", (double)x[0], (double)x[1]));
  SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED,
          "%s:%" PetscInt_FMT ": %s \"%s\"%s at %s is not in the liquid region: %s; the nearest wall, \"%s\", is %g m "
          "away (a point on a wall must be within dx/2 = %g of it). Probes and gauges read the liquid or a wall's "
          "pressure: move it into the tank's liquid or onto the wall's face",
          ps->file, it->line, what, it->name, it->gauge ? (x == it->x0 ? " (its start)" : " (its end)") : "", at,
          inbox ? "it lies beyond the tank's walls or inside a wall's thickness (a baffle, a rib, an obstacle)"
                : "it lies outside the tank's walls (their bounding box)",
          wall >= 0 && wall < nwalls ? names[wall] : "?", (double)dist, (double)(0.5 * pv->dx));
}

/* the signed distance of x from element e's plane, positive on the solid's side (the normal points out of the liquid)
 */
static PetscReal FSProbesSide(const FSWallView *B, PetscInt e, const PetscReal x[])
{
  const PetscReal *c = &B->element[e * B->stride + B->centroid], *n = &B->element[e * B->stride + B->normal];
  PetscReal        d = 0;
  for (PetscInt a = 0; a < B->dim; a++) d += (x[a] - c[a]) * n[a];
  return d;
}

/* a probe on a wall (its nearest element near) strictly inside a wall's solid and within dx/2 of two opposite faces
   (a baffle or a rib thinner than dx): which side it should read is not known, an error. On a face itself it reads
   that face. */
static PetscErrorCode FSProbesCheckFaces(const FSProbeSet *ps, const FSSolverParticleView *pv, MPI_Comm comm,
                                         const FSProbe *it, const FSWallView *B, PetscInt near)
{
  const PetscInt     dim = pv->dim;
  const PetscReal   *nn = &B->element[near * B->stride + B->normal], tol = 1e-6 * pv->dx;
  PetscInt           nwalls;
  const char *const *names;

  PetscFunctionBegin;
  if (FSProbesSide(B, near, it->x0) <= tol) PetscFunctionReturn(0);
  PetscCall(FSBoundaryGetWallNames(pv->boundary, &nwalls, &names));
  for (PetscInt e = 0; e < B->nelements; e++) {
    const PetscReal *n = &B->element[e * B->stride + B->normal];
    PetscReal        dn, lat, nn_n = 0;
    PetscBool        over;
    FSProbesElementDistance(B, e, it->x0, 0.5 * pv->dx, &dn, &over, &lat);
    for (PetscInt a = 0; a < dim; a++) nn_n += nn[a] * n[a];
    PetscCheck(
        !(over && dn < 0.5 * pv->dx && nn_n < 0 && FSProbesSide(B, e, it->x0) > tol), comm, PETSC_ERR_FILE_UNEXPECTED,
        "%s:%" PetscInt_FMT ": probe \"%s\" lies inside the thickness of a wall, within dx/2 = %g of two "
        "opposite faces (of walls \"%s\" and \"%s\"): which side it should read is not known. Put it on "
        "the face it should read",
        ps->file, it->line, it->name, (double)(0.5 * pv->dx), names[B->elementwall[near]], names[B->elementwall[e]]);
  }
  PetscFunctionReturn(0);
}

/*
   FSProbeSetSetUp - reads the file of -fs_probes (ps->file, "" for none: the monitor's options), checks the items
   against the domain, finds the wall elements of the probes on walls and the samples of the gauges with the walls'
   Shepard factor at each. Called by the probes monitor's set-up, which the solver's set-up calls.

   Collective
*/
PetscErrorCode FSProbeSetSetUp(FSProbeSet *ps, FSSolver s)
{
  MPI_Comm                    comm = PetscObjectComm((PetscObject)s);
  FSSolverParticleView        view;
  const FSSolverParticleView *pv = &view;
  PetscInt                    dim;
  PetscReal                   dx;
  const FSWallView           *B    = NULL;
  char                       *text = NULL;
  PetscInt                    nv = 0, cap = 0, nbare = 0, firstbare = -1;
  PetscReal                   bare_area = 0;

  PetscFunctionBegin;
  PetscCall(FSSolverGetParticleView(s, &view));
  dim      = view.dim;
  dx       = view.dx;
  ps->step = -1;
  if (!ps->file[0]) PetscFunctionReturn(0);
  PetscCall(FSProbesReadFile(comm, ps->file, &text));
  PetscCall(FSProbesParse(ps, pv, comm, text));
  PetscCall(PetscFree(text));
  /* every wall element, numbered among all of them: the probes keep those numbers (FSBoundaryLocalElement finds an
     element in this rank's view at each sample, wherever the cuts have moved) */
  if (pv->boundary) PetscCall(FSBoundaryGetFullView(pv->boundary, &B));
  /* the probes on walls: the nearest element, or the elements within the face */
  for (PetscInt k = 0; k < ps->n; k++) {
    FSProbe *it = &ps->item[k];
    it->estart = it->eend = ps->nelem;
    if (it->gauge) {
      PetscReal L = 0, dev = 0;
      if (pv->boundary) {
        PetscCall(FSProbesCheckInLiquid(ps, pv, comm, it, it->x0, PETSC_FALSE, "gauge"));
        PetscCall(FSProbesCheckInLiquid(ps, pv, comm, it, it->x1, PETSC_FALSE, "gauge"));
      }
      for (PetscInt d = 0; d < dim; d++) L += PetscSqr(it->x1[d] - it->x0[d]);
      L = PetscSqrtReal(L);
      for (PetscInt d = 0; d < dim; d++)
        if (d != 1) dev = PetscMax(dev, PetscAbsReal(it->x1[d] - it->x0[d]));
      it->vertical = (PetscBool)(dev <= 1e-12 * L);
      it->sample   = ps->nsamples;
      it->nsample  = (PetscInt)PetscCeilReal(L / (0.25 * dx) - 1e-9) + 1; /* spaced at most dx/4 */
      ps->nsamples += it->nsample;
      continue;
    }
    if (B && B->nelements) {
      PetscInt  near = -1;
      PetscReal best = PETSC_MAX_REAL, bestlat = PETSC_MAX_REAL, dn, lat;
      PetscBool over;
      for (PetscInt e = 0; e < B->nelements; e++) { /* the nearest element among those x lies over; of the elements
                                                        of one plane, the one whose centroid is nearest along it */
        FSProbesElementDistance(B, e, it->x0, 0.5 * dx, &dn, &over, &lat);
        if (over && (dn < best - 1e-9 * dx || (dn <= best + 1e-9 * dx && lat < bestlat))) {
          best    = dn;
          bestlat = lat;
          near    = e;
        }
      }
      if (near >= 0 && best < 0.5 * dx) {
        PetscCall(FSProbesCheckFaces(ps, pv, comm, it, B, near));
        if (it->diameter > 0) PetscCall(FSProbesFace(B, it, near, dx, ps, &cap));
        if (ps->nelem == it->estart) { /* no diameter, or no element within the face */
          PetscCall(FSProbesAddElement(ps, &cap, near, B->element[near * B->stride + B->measure]));
        }
        if (!(it->diameter > 0)) {
          if (!nbare++) firstbare = k;
          bare_area += B->element[near * B->stride + B->measure];
        }
      }
      it->eend = ps->nelem;
    }
    if (pv->boundary) PetscCall(FSProbesCheckInLiquid(ps, pv, comm, it, it->x0, it->eend > it->estart, "probe"));
  }
  if (nbare) { /* a probe on a wall without a diameter: the pressure of one element (dx long in 2-D, edge h in 3-D) */
    const PetscReal mean = bare_area / nbare, across = dim == 2 ? mean : PetscSqrtReal(4 * mean / PETSC_PI);
    const FSProbe  *it = &ps->item[firstbare];
    char            size[96];
    if (dim == 2) PetscCall(PetscSNPrintf(size, sizeof(size), "a segment %.3g m long", (double)mean));
    else PetscCall(PetscSNPrintf(size, sizeof(size), "%.3g m^2, a disc %.3g m across", (double)mean, (double)across));
    PetscCall(PetscPrintf(comm,
                          "Warning: %s: %" PetscInt_FMT " probe(s) on a wall without a diameter (the first: \"%s\", "
                          "line %" PetscInt_FMT "): each reads the wall pressure of its nearest wall element alone, on "
                          "average %s (%.2g dx), not the face of a sensor: give \"diameter D\" (the sensor's) to "
                          "average the wall pressure over it\n",
                          ps->file, nbare, it->name, it->line, size, (double)(across / dx)));
  }
  /* the columns: per probe its pressure and velocity, per gauge its elevation */
  PetscCall(PetscMalloc2(ps->n + 1, &ps->offset, ps->n, &ps->names));
  for (PetscInt k = 0; k < ps->n; k++) {
    ps->offset[k] = nv;
    ps->names[k]  = ps->item[k].name;
    nv += ps->item[k].gauge ? 1 : 1 + dim + (ps->item[k].filtered ? 1 : 0);
  }
  ps->offset[ps->n] = nv;
  ps->nvalues       = nv;
  PetscCall(PetscMalloc1(nv + 1, &ps->colname));
  for (PetscInt k = 0; k < ps->n; k++) {
    const FSProbe *it                  = &ps->item[k];
    char(*col)[FS_PROBE_NAME_LEN + 32] = &ps->colname[ps->offset[k]];
    if (it->gauge) {
      PetscCall(
          PetscSNPrintf(col[0], sizeof(col[0]), "%s_%s[m]", it->name, it->vertical ? "elevation" : "elevation_along"));
    } else {
      static const char *ax[] = {"x", "y", "z"};
      PetscCall(PetscSNPrintf(col[0], sizeof(col[0]), "%s_pressure[Pa]", it->name));
      for (PetscInt d = 0; d < dim; d++)
        PetscCall(PetscSNPrintf(col[1 + d], sizeof(col[0]), "%s_velocity_%s[m/s]", it->name, ax[d]));
      if (it->filtered) PetscCall(PetscSNPrintf(col[1 + dim], sizeof(col[0]), "%s_pressure_filtered[Pa]", it->name));
    }
  }
  PetscCall(PetscMalloc3(nv + 1, &ps->values, ps->nsamples + 1, &ps->sgamma, ps->n * (3 + dim) + ps->nsamples + 1,
                         &ps->sums));
  /* the walls' Shepard factor at the gauges' samples; a sample on a wall's line is moved into the liquid by
     1e-6 dx (on the wall itself the wall's own half of the support does not count) */
  for (PetscInt k = 0; k < ps->n; k++) {
    const FSProbe *it = &ps->item[k];
    if (!it->gauge) continue;
    for (PetscInt q = 0; q < it->nsample; q++) {
      PetscReal x[3] = {0, 0, 0}, *gam = &ps->sgamma[it->sample + q];
      for (PetscInt d = 0; d < dim; d++) x[d] = it->x0[d] + (it->x1[d] - it->x0[d]) * q / (it->nsample - 1);
      *gam = 1;
      if (!B) continue;
      for (PetscInt e = 0; e < B->nelements; e++) {
        const PetscReal *nrm = &B->element[e * B->stride + B->normal];
        PetscReal        dn;
        PetscBool        over;
        FSProbesElementDistance(B, e, x, 1e-9 * dx, &dn, &over, NULL);
        if (over && dn < 1e-9 * dx)
          for (PetscInt d = 0; d < dim; d++) x[d] -= 1e-6 * dx * nrm[d];
      }
      PetscCall(FSBoundaryShepardAt(pv->boundary, x, gam));
    }
  }
  if (pv->boundary) PetscCall(FSBoundaryRestoreFullView(pv->boundary, &B));
  ps->step = -1;
  PetscFunctionReturn(0);
}

/* the body acceleration at x (the coupling's frame field, gravity without a coupling) */
static inline void FSProbesBody(const FSFrameField *body, PetscInt dim, const PetscReal x[], PetscReal g[])
{
  if (dim == 2) FSFrameFieldEval(body, x, g);
  else FSFrameFieldEval3(body, x, g);
}

/*
   FSProbeSetSample - the probes' and gauges' values at the current state: one evaluation of the
   right-hand side, this rank's sums over its owned particles, one MPI_Allreduce of all the sums.

   Collective
*/
PetscErrorCode FSProbeSetSample(FSProbeSet *ps, FSSolver s)
{
  FSSolverParticleView        view;
  const FSSolverParticleView *pv = &view;
  PetscInt                    dim, S, PS, n;
  PetscReal                   R, R2;
  const FSFrameField         *body;
  PetscReal                  *sum, *ssum;
  const FSWallView           *B = NULL;

  PetscFunctionBegin;
  PetscCall(FSSolverGetTime(s, &ps->time, &ps->step));
  PetscCall(FSSolverGetParticleView(s, &view));
  /* the records, volumes, pressures, body field and wall pressure of the state */
  if (view.nglobal > 0) {
    PetscCall(FSSolverEvaluateAtState(s, ps->time));
    PetscCall(FSSolverGetParticleView(s, &view)); /* the arrays as the evaluation left them */
  }
  dim  = view.dim;
  S    = view.stride;
  PS   = 3 + dim;
  n    = view.nowned;
  R    = view.kernel->support;
  R2   = view.kernel->support2;
  sum  = ps->sums;
  ssum = ps->sums + ps->n * PS;
  PetscCall(PetscArrayzero(ps->sums, ps->n * PS + ps->nsamples));
  PetscCall(FSCouplingGetBody(pv->coupling, &body));
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *xi = &pv->rec[i * S], rho = xi[2 * dim], V = pv->vol[i], p = pv->pressure[i];
    for (PetscInt k = 0; k < ps->n; k++) {
      const FSProbe *it = &ps->item[k];
      if (!it->gauge) {
        PetscReal r2 = 0, W, g[3], mid[3], gx = 0, *sk = &sum[k * PS];
        for (PetscInt a = 0; a < dim; a++) r2 += PetscSqr(it->x0[a] - xi[a]);
        if (r2 >= R2) continue;
        W = FSKernelW(pv->kernel, PetscSqrtReal(r2)) * V;
        for (PetscInt a = 0; a < dim; a++) mid[a] = 0.5 * (it->x0[a] + xi[a]);
        FSProbesBody(body, dim, mid, g);
        for (PetscInt a = 0; a < dim; a++) gx += g[a] * (it->x0[a] - xi[a]);
        sk[0] += (p + rho * gx) * W;
        for (PetscInt a = 0; a < dim; a++) sk[1 + a] += xi[dim + a] * W;
        sk[1 + dim] += W;
      } else { /* the samples within the support: those whose distance along the line is within R */
        PetscReal L = 0, t = 0, e[3], ds;
        PetscInt  q0, q1;
        for (PetscInt a = 0; a < dim; a++) L += PetscSqr(it->x1[a] - it->x0[a]);
        L  = PetscSqrtReal(L);
        ds = L / (it->nsample - 1);
        for (PetscInt a = 0; a < dim; a++) {
          e[a] = (it->x1[a] - it->x0[a]) / L;
          t += (xi[a] - it->x0[a]) * e[a];
        }
        q0 = PetscMax(0, (PetscInt)PetscCeilReal((t - R) / ds));
        q1 = PetscMin(it->nsample - 1, (PetscInt)PetscFloorReal((t + R) / ds));
        for (PetscInt q = q0; q <= q1; q++) {
          PetscReal r2 = 0;
          for (PetscInt a = 0; a < dim; a++)
            r2 += PetscSqr(it->x0[a] + (it->x1[a] - it->x0[a]) * q / (it->nsample - 1) - xi[a]);
          if (r2 < R2) ssum[it->sample + q] += FSKernelW(pv->kernel, PetscSqrtReal(r2)) * V;
        }
      }
    }
  }
  if (pv->boundary) { /* a probe on a wall: the wall pressure times the area of the elements this rank owns (their
                       wall pressure is known on their owner), summed over the ranks with the rest */
    const PetscInt  *wstart, *wk;
    const PetscReal *wW;
    PetscCall(FSBoundaryGetView(pv->boundary, &B, &wstart, &wk, &wW));
    for (PetscInt k = 0; k < ps->n && B && B->pressure; k++) {
      const FSProbe *it = &ps->item[k];
      if (it->gauge) continue;
      for (PetscInt q = it->estart; q < it->eend; q++) {
        PetscInt  e;
        PetscBool owns = PETSC_FALSE;
        PetscCall(FSBoundaryLocalElement(pv->boundary, ps->elem[q], &e));
        if (e >= 0) PetscCall(FSBoundaryOwnsElement(pv->boundary, e, &owns));
        if (owns) sum[k * PS + 2 + dim] += B->pressure[e] * ps->ewt[q];
      }
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, ps->sums, (PetscMPIInt)(ps->n * PS + ps->nsamples), MPIU_REAL, MPI_SUM,
                             PetscObjectComm((PetscObject)s)));
  for (PetscInt k = 0; k < ps->n; k++) {
    const FSProbe *it = &ps->item[k];
    PetscReal     *v  = &ps->values[ps->offset[k]];
    if (!it->gauge) {
      const PetscReal *sk = &sum[k * PS];
      if (sk[1 + dim] > 0) {
        v[0] = sk[0] / sk[1 + dim];
        for (PetscInt a = 0; a < dim; a++) v[1 + a] = sk[1 + a] / sk[1 + dim];
      } else { /* no liquid within the support */
        v[0] = pv->background_pressure;
        for (PetscInt a = 0; a < dim; a++) v[1 + a] = 0;
      }
      if (it->eend > it->estart && B && B->pressure) { /* on a wall: the wall pressure, averaged over the face */
        PetscReal a = 0;
        for (PetscInt q = it->estart; q < it->eend; q++) a += ps->ewt[q];
        v[0] = sk[2 + dim] / a;
      }
      if (it->filtered) { /* the reading of the last sample of probes.csv (the raw value before the first) */
        const FSSensorFilter *f = &it->filter;
        v[1 + dim]              = f->started ? (f->rate > 0 ? f->held : f->y[0]) : v[0];
      }
    } else { /* the first sample, from the start, where S/gamma falls below 1/2 */
      const PetscReal *Sq = &ssum[it->sample], *gq = &ps->sgamma[it->sample];
      PetscReal        L = 0, tcross, rprev = 0;
      PetscInt         q;
      for (PetscInt a = 0; a < dim; a++) L += PetscSqr(it->x1[a] - it->x0[a]);
      L      = PetscSqrtReal(L);
      tcross = L;
      for (q = 0; q < it->nsample; q++) {
        const PetscReal r = gq[q] > 1e-6 ? Sq[q] / gq[q] : 0;
        if (r < 0.5) {
          tcross = q == 0 ? 0 : (q - 1 + (rprev - 0.5) / (rprev - r)) * L / (it->nsample - 1);
          break;
        }
        rprev = r;
      }
      v[0] = it->vertical ? it->x0[1] + (it->x1[1] > it->x0[1] ? tcross : -tcross) : tcross;
    }
  }
  PetscFunctionReturn(0);
}

/*
   FSProbeSetRecord - the values of a row of probes.csv at the current state (in ps->time, ps->values): the probes and
   gauges sampled, and the sensors' time response (their filters and sample-and-hold) advanced to this sample, which
   only the rows of probes.csv do.

   Collective
*/
PetscErrorCode FSProbeSetRecord(FSProbeSet *ps, FSSolver s)
{
  PetscInt dim;

  PetscFunctionBegin;
  PetscCall(FSProbeSetSample(ps, s));
  PetscCall(FSSolverGetDimension(s, &dim));
  for (PetscInt k = 0; k < ps->n; k++) { /* the sensors' time response: only the samples of probes.csv */
    FSProbe *it = &ps->item[k];
    if (it->filtered)
      ps->values[ps->offset[k] + 1 + dim] = FSSensorFilterUpdate(&it->filter, ps->time, ps->values[ps->offset[k]]);
  }
  PetscFunctionReturn(0);
}

/* FSProbeSetDestroy - frees the probes. */
PetscErrorCode FSProbeSetDestroy(FSProbeSet *ps)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(ps->item));
  PetscCall(PetscFree2(ps->elem, ps->ewt));
  PetscCall(PetscFree2(ps->offset, ps->names));
  PetscCall(PetscFree(ps->colname));
  PetscCall(PetscFree3(ps->values, ps->sgamma, ps->sums));
  ps->n = ps->nvalues = ps->nsamples = ps->nelem = 0;
  PetscFunctionReturn(0);
}
