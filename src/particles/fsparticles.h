/*
   The particles' geometry (src/particles): the smoothing kernel, the decomposition of the domain over
   the ranks, the halo of ghost particles and the cell and neighbour lists. Plain data structures that
   know nothing of the solver: they take arrays of particle records.
*/
#pragma once
#include <flexslosh.h> /* FS_ALWAYS_INLINE */
#include <petscsf.h>
#include <stdint.h>

/* Wendland C2 kernel with support 2h, dimension 2 or 3. */
typedef struct {
  PetscInt  dim;
  PetscReal h, support, support2;
  PetscReal wnorm; /* W(q) = wnorm (1 - q/2)^4 (2q + 1) */
  PetscReal fnorm; /* grad_i W = fnorm (1 - q/2)^3 (x_i - x_j), i.e. F(r) = W'(r)/r */
} FSKernel;

PETSC_INTERN PetscErrorCode FSKernelSetUp(FSKernel *, PetscInt dim, PetscReal h);
static inline PetscReal     FSKernelW(const FSKernel *k, PetscReal r)
{
  const PetscReal q = r / k->h, a = 1.0 - 0.5 * q;
  return q >= 2.0 ? 0.0 : k->wnorm * a * a * a * a * (2.0 * q + 1.0);
}
/* F(r) such that grad_i W(x_i - x_j) = F(r) (x_i - x_j); valid for r < 2h. */
static inline PetscReal FSKernelF(const FSKernel *k, PetscReal r)
{
  const PetscReal a = 1.0 - 0.5 * r / k->h;
  return k->fnorm * a * a * a;
}

/* Orthogonal process grid over the domain box: rank (i,j,k) owns
   [cut[d][i_d], cut[d][i_d+1]) in every direction d. */
typedef struct {
  PetscInt    dim;
  PetscReal   lo[3], hi[3], len[3];
  PetscBool   periodic[3];
  PetscMPIInt size, rank;
  PetscMPIInt np[3];    /* ranks per direction */
  PetscMPIInt coord[3]; /* this rank's position in the grid */
  PetscReal  *cut[3];   /* np[d]+1 cut positions per direction */
} FSDecomp;

PETSC_INTERN PetscErrorCode FSDecompSetUp(FSDecomp *, MPI_Comm, PetscInt dim, const PetscReal lo[],
                                          const PetscReal hi[], const PetscBool periodic[], PetscReal minwidth);
PETSC_INTERN PetscErrorCode FSDecompBalance(FSDecomp *, MPI_Comm, PetscInt n, const PetscReal x[], PetscReal minwidth);
PETSC_INTERN PetscErrorCode FSDecompDestroy(FSDecomp *);
PETSC_INTERN PetscInt       FSDecompLayoutSize(const FSDecomp *);
PETSC_INTERN PetscErrorCode FSDecompGetLayout(const FSDecomp *, PetscReal v[]);
PETSC_INTERN PetscErrorCode FSDecompSetLayout(FSDecomp *, PetscInt n, const PetscReal v[], PetscBool *taken);
PETSC_INTERN PetscMPIInt    FSDecompRankOf(const FSDecomp *, const PetscReal x[]);
PETSC_INTERN PetscMPIInt    FSDecompRankAt(const FSDecomp *, const PetscMPIInt c[]);

/* Ghost particles: copies of owned particles of other ranks (or periodic images of this rank's)
   within the halo width of this rank's subdomain. Refreshed through a PetscSF each RHS. */
typedef struct {
  PetscInt     nghost, cap;
  PetscReal   *shift; /* nghost*dim periodic shift added after each refresh */
  PetscSF      sf;    /* roots: owned records, leaves: ghost records */
  MPI_Datatype rectype, auxtype;
  PetscInt     recstride, auxstride;
  /* send-side work for building */
  PetscInt     nsend, sendcap;
  PetscInt    *send_index;
  PetscMPIInt *send_rank;
  PetscReal   *send_shift;
  /* communication counts (the run's parallel statistics): per refresh, the messages to other ranks and the
     records they carry, set by each build; totals since the halo was created, added where messages are posted */
  PetscInt       nsendranks, nsendremote;
  PetscLogDouble refresh_msgs, refresh_bytes; /* the refreshes' messages and bytes sent */
  PetscLogDouble build_msgs, build_bytes;     /* the builds' (the ranks' handshake and the ghosts' addresses) */
  PetscInt       nbuilds;
} FSHalo;

PETSC_INTERN PetscErrorCode FSHaloBuild(FSHalo *, MPI_Comm, const FSDecomp *, PetscInt nowned, const PetscReal rec[],
                                        PetscInt stride, PetscReal width);
PETSC_INTERN PetscErrorCode FSHaloRefresh(FSHalo *, PetscInt dim, PetscInt nowned, PetscReal rec[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshAux(FSHalo *, PetscReal aux[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshScalar(FSHalo *, PetscReal a[]);
PETSC_INTERN PetscErrorCode FSHaloDestroy(FSHalo *);

/* Cell-linked list (counting sort) and the candidate (Verlet) lists of the owned particles. A particle's
   candidates are the particles of the rows of cells around its cell (FSNeighboursRows: 3 rows of 3 cells
   in 2-D, 9 in 3-D, contiguous in the cell-sorted order) within the candidate radius; they are kept as one
   bit per position of those rows, set for a candidate (about 225 bits for 64 candidates in 2-D, 3,400 for
   520 in 3-D: an eighth of a list of 4-byte indices), and read back through the cell list. No list of the
   pairs within the support is kept: each pass over the pairs picks them from the candidates
   (FSNeighboursPick) as it visits them, which costs a distance per candidate and saves the list's memory. */
typedef struct {
  PetscInt  dim;
  PetscReal lo[3], cellsize;
  PetscInt  nc[3], ncells;
  PetscInt *cellstart; /* ncells+1 */
  PetscInt *cellof;    /* cell of each particle */
  PetscInt *order;     /* particles sorted by cell */
  PetscInt  ncap, ccap;
  /* the candidates, built when the lists are rebuilt (with the cell list, which must not change until the next
     build): particle i's bits are the words mask[mstart[i] .. mstart[i+1]) */
  PetscInt  *mstart; /* nowned+1 */
  uint64_t  *mask;
  PetscInt   scap, mcap;
  PetscInt64 ncand;   /* the candidates (set bits) */
  PetscInt   maxcand; /* the most candidates of one particle */
  PetscInt64 npairs;  /* the pairs within the support at the last right-hand side (set by its pass) */
} FSNeighbours;

PETSC_INTERN PetscErrorCode FSNeighboursBuildCells(FSNeighbours *, PetscInt dim, PetscInt n, const PetscReal rec[],
                                                   PetscInt stride, PetscReal cellsize);
PETSC_INTERN PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *, PetscInt nowned, const PetscReal rec[],
                                                        PetscInt stride, PetscReal radius);

#define FS_NEIGHBOUR_ROWS 9 /* the most rows of cells around a cell (3-D) */

/*
   FSNeighboursRows - the rows of cells around particle i's cell (its cell at the last build of the cell
   list): the first position q0[r] of each in the cell-sorted order and its length len[r]; returns their
   number. A particle's candidate bits number the positions of these rows one after the other.
*/
static inline PetscInt FSNeighboursRows(const FSNeighbours *nb, PetscInt i, PetscInt q0[], PetscInt len[])
{
  const PetscInt nx = nb->nc[0], ny = nb->nc[1], nz = nb->nc[2], c = nb->cellof[i];
  const PetscInt cx = c % nx, cy = (c / nx) % ny, cz = c / (nx * ny);
  PetscInt       nr = 0;

  for (PetscInt z = PetscMax(cz - 1, 0); z <= PetscMin(cz + 1, nz - 1); z++)
    for (PetscInt y = PetscMax(cy - 1, 0); y <= PetscMin(cy + 1, ny - 1); y++) {
      const PetscInt row = nx * (y + ny * z);
      q0[nr]             = nb->cellstart[row + PetscMax(cx - 1, 0)];
      len[nr]            = nb->cellstart[row + PetscMin(cx + 1, nx - 1) + 1] - q0[nr];
      nr++;
    }
  return nr;
}

/* Iterating over a particle's candidates (FSNeighboursCandidateBegin / Next / Drop), in the order of the
   positions of its rows. */
typedef struct {
  PetscInt  q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS];
  PetscInt  r, rstart, rend, k, nw, p;
  uint64_t  bits;
  uint64_t *w;
} FSCandidateIter;

static inline void FSNeighboursCandidateBegin(const FSNeighbours *nb, PetscInt i, FSCandidateIter *it)
{
  (void)FSNeighboursRows(nb, i, it->q0, it->len);
  it->r      = 0;
  it->rstart = 0;
  it->rend   = it->len[0];
  it->w      = nb->mask + nb->mstart[i];
  it->nw     = nb->mstart[i + 1] - nb->mstart[i];
  it->k      = 0;
  it->bits   = it->nw ? it->w[0] : 0;
  it->p      = -1;
}

/* the next candidate's index into j; PETSC_FALSE after the last */
static inline PetscBool FSNeighboursCandidateNext(const FSNeighbours *nb, FSCandidateIter *it, PetscInt *j)
{
  while (!it->bits) {
    if (++it->k >= it->nw) return PETSC_FALSE;
    it->bits = it->w[it->k];
  }
  it->p = 64 * it->k + __builtin_ctzll(it->bits);
  it->bits &= it->bits - 1;
  while (it->p >= it->rend) {
    it->rstart = it->rend;
    it->rend += it->len[++it->r];
  }
  *j = nb->order[it->q0[it->r] + it->p - it->rstart];
  return PETSC_TRUE;
}

/* removes the candidate FSNeighboursCandidateNext() returned last (e.g. a pair a wall cuts) */
static inline void FSNeighboursCandidateDrop(FSNeighbours *nb, FSCandidateIter *it)
{
  it->w[it->p >> 6] &= ~((uint64_t)1 << (it->p & 63));
  nb->ncand--;
}

/*
   FSNeighboursPick - the neighbours j != i of owned particle i within r^2 < R2 at the current positions
   (records rec with stride, position first), picked from its candidates: their indices into j[], x_j - x_i
   into dx[] (dim a pair) and r^2 into r2[]; returns their number (at most nb->maxcand, which bounds the
   arrays). Without branches on the distance: whether a candidate is inside is as good as random, and
   mispredicted branches cost more than the stores, so every candidate is written at the end of the arrays,
   which moves on only for those inside. Inlined, so that a caller with a constant dim gets the loop for its
   dimension.
*/
FS_ALWAYS_INLINE PetscInt FSNeighboursPick(const FSNeighbours *nb, const PetscInt dim, PetscInt i,
                                           const PetscReal rec[], PetscInt stride, PetscReal R2, PetscInt j[],
                                           PetscReal dx[], PetscReal r2[])
{
  const PetscReal *xi = &rec[i * stride];
  const uint64_t  *w  = nb->mask + nb->mstart[i];
  const PetscInt   nw = nb->mstart[i + 1] - nb->mstart[i];
  PetscInt         q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], nc = 0, m = 0, r = 0, rstart = 0, rend;

  /* the candidates' indices first (integer work only), then their distances in a loop of their own */
  (void)FSNeighboursRows(nb, i, q0, len);
  rend = len[0];
  for (PetscInt k = 0; k < nw; k++)
    for (uint64_t bits = w[k]; bits; bits &= bits - 1) {
      const PetscInt p = 64 * k + __builtin_ctzll(bits);
      while (p >= rend) { /* the next row (a branch taken a few times a particle) */
        rstart = rend;
        rend += len[++r];
      }
      j[nc++] = nb->order[q0[r] + p - rstart];
    }
  for (PetscInt q = 0; q < nc; q++) {
    const PetscInt   c  = j[q];
    const PetscReal *xc = &rec[c * stride];
    PetscReal        d2 = 0;
    for (PetscInt a = 0; a < dim; a++) {
      const PetscReal d = xc[a] - xi[a];
      dx[m * dim + a]   = d;
      d2 += d * d;
    }
    j[m]  = c;
    r2[m] = d2;
    m += d2 < R2;
  }
  return m;
}
PETSC_INTERN PetscErrorCode FSNeighboursDestroy(FSNeighbours *);
