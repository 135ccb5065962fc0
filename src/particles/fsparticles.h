/*
   The particles' geometry (src/particles): the smoothing kernel, the decomposition of the domain over
   the ranks, the halo of ghost particles and the cell and neighbour lists. Plain data structures that
   know nothing of the solver: they take arrays of particle records.
*/
#pragma once
#include <flexslosh.h> /* FS_ALWAYS_INLINE */
#include <petscsf.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h> /* memcpy */

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
PETSC_INTERN PetscErrorCode FSDecompBalance(FSDecomp *, MPI_Comm, PetscInt n, const PetscReal x[], const PetscInt64 w[],
                                            PetscReal minwidth);
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
PETSC_INTERN PetscErrorCode FSHaloRefreshBegin(FSHalo *, PetscReal rec[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshEnd(FSHalo *, PetscInt dim, PetscInt nowned, PetscReal rec[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshAux(FSHalo *, PetscReal aux[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshAuxBegin(FSHalo *, PetscReal aux[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshAuxEnd(FSHalo *, PetscReal aux[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshScalar(FSHalo *, PetscReal a[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshScalarBegin(FSHalo *, PetscReal a[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshScalarEnd(FSHalo *, PetscReal a[]);
PETSC_INTERN PetscErrorCode FSHaloDestroy(FSHalo *);

/*
   FSCommProgress - called with the index i of a long loop over particles: every FS_PROGRESS_INTERVAL particles lets
   MPI move the messages in flight (an MPI_Iprobe, under a microsecond). Open MPI moves a large message only inside
   MPI calls of both ranks, so without it a rank that sends and receives in a halo refresh waits in its ...End until
   the other rank reaches its own: the passes between a Begin and its End would not overlap the messages.
*/
#define FS_PROGRESS_INTERVAL 256
static inline void FSCommProgress(PetscInt i)
{
  if ((i & (FS_PROGRESS_INTERVAL - 1)) == FS_PROGRESS_INTERVAL - 1) {
    int flag;
    (void)MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_SELF, &flag, MPI_STATUS_IGNORE);
  }
}

/* Cell-linked list (counting sort) and the candidate (Verlet) lists of the owned particles. A particle's
   candidates are the particles of the rows of cells around its cell (FSNeighboursRows: 3 rows of 3 cells
   in 2-D, 9 in 3-D, contiguous in the cell-sorted order) within the candidate radius, kept in one of two
   forms (FSNeighboursForm): their indices (4 bytes a candidate), or one bit per position of those rows, set
   for a candidate and read back through the cell list (about 6 words for 64 candidates in 2-D, 54 for 520
   in 3-D: a fifth of the indices' memory, for a few per cent more time in each pass). The first pass over the
   pairs of a right-hand side picks the pairs within the support from the candidates (FSNeighboursPick) as it visits
   them; the solver's pair cache (-fs_pair_cache) keeps what it picked for the passes that follow, else they pick
   again. */
typedef enum {
  FS_CANDIDATES_INDICES, /* cand[cstart[i] .. cend[i]) */
  FS_CANDIDATES_BITS     /* the words mask[cstart[i] .. cstart[i+1]), each row of cells from a word of its own */
} FSNeighboursForm;

typedef struct {
  PetscInt  dim;
  PetscReal lo[3], cellsize;
  PetscInt  nc[3], ncells;
  PetscInt *cellstart; /* ncells+1 */
  PetscInt *cellof;    /* cell of each particle */
  PetscInt *order;     /* particles sorted by cell */
  PetscInt  ncap, ccap;
  /* the candidates, built when the lists are rebuilt (with the cell list, which must not change until the next
     build while the candidates are bits) */
  FSNeighboursForm form;
  PetscInt        *cstart, *cend; /* nowned+1: the first index or word of each particle; the end of its indices */
  PetscInt        *cand;
  uint64_t        *mask;
  PetscInt         scap, ccandcap, mcap;
  PetscInt64       ncand;   /* the candidates */
  PetscInt         maxcand; /* the most candidates of one particle */
  PetscInt64       npairs;  /* the pairs within the support at the last right-hand side (set by its pass) */
} FSNeighbours;

PETSC_INTERN PetscErrorCode FSNeighboursBuildCells(FSNeighbours *, PetscInt dim, PetscInt n, const PetscReal rec[],
                                                   PetscInt stride, PetscReal cellsize);
PETSC_INTERN PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *, PetscInt nowned, const PetscReal rec[],
                                                        PetscInt stride, PetscReal radius);

#define FS_NEIGHBOUR_ROWS 9 /* the most rows of cells around a cell (3-D) */

PETSC_INTERN PetscErrorCode FSNeighboursSplitByGhosts(const FSNeighbours *, PetscInt nowned, PetscInt ntotal,
                                                      PetscInt pass[], PetscInt *ninterior);

/*
   FSNeighboursRows - the rows of cells around particle i's cell (its cell at the last build of the cell
   list; the cell list's layer of empty cells makes them all exist): the first position q0[r] of each in the
   cell-sorted order and its length len[r]; returns their number (3 in 2-D, 9 in 3-D). A particle's
   candidate bits number the positions of each row from a word of their own, row after row.
*/
static inline PetscInt FSNeighboursRows(const FSNeighbours *nb, PetscInt i, PetscInt q0[], PetscInt len[])
{
  const PetscInt nx = nb->nc[0], nxy = nb->nc[0] * nb->nc[1], c = nb->cellof[i], z0 = nb->dim == 3 ? -1 : 0;
  PetscInt       nr = 0;

  for (PetscInt z = z0; z <= -z0; z++)
    for (PetscInt y = -1; y <= 1; y++) {
      const PetscInt mid = c + y * nx + z * nxy;
      q0[nr]             = nb->cellstart[mid - 1];
      len[nr]            = nb->cellstart[mid + 2] - q0[nr];
      nr++;
    }
  return nr;
}

/* Iterating over a particle's candidates (FSNeighboursCandidateBegin / Next / Drop), in the order of the
   positions of its rows. A plain iteration writes nothing; after a Drop the iteration must run to its end
   (with the candidates as indices, those that follow a dropped one move up as it goes). */
typedef struct {
  PetscInt  i, q, wq;                                      /* indices: the particle, the read and write positions */
  PetscInt *wcand, *wend;                                  /* indices, after a Drop: the list and the particle's end */
  PetscInt  q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS]; /* bits: the rows */
  PetscInt  nr, r, k, nwr;                                 /* bits: the row, the word within it, the row's words */
  uint64_t  bits, cur; /* bits: the word's bits not visited yet, the bit of the candidate last returned */
  uint64_t *w;         /* bits: the row's first word */
} FSCandidateIter;

static inline void FSNeighboursCandidateBegin(const FSNeighbours *nb, PetscInt i, FSCandidateIter *it)
{
  it->i = i;
  it->q = it->wq = nb->cstart[i];
  it->wcand = it->wend = NULL;
  it->nr = it->r = it->k = it->nwr = 0;
  it->bits = it->cur = 0;
  it->w              = NULL;
  if (nb->form == FS_CANDIDATES_INDICES) return;
  it->nr   = FSNeighboursRows(nb, i, it->q0, it->len);
  it->w    = nb->mask + nb->cstart[i];
  it->nwr  = (it->len[0] + 63) / 64;
  it->bits = it->nwr ? it->w[0] : 0;
}

/* the next candidate's index into j; PETSC_FALSE after the last */
static inline PetscBool FSNeighboursCandidateNext(const FSNeighbours *nb, FSCandidateIter *it, PetscInt *j)
{
  PetscInt p;

  if (nb->form == FS_CANDIDATES_INDICES) {
    if (it->q >= nb->cend[it->i]) {
      if (it->wend) *it->wend = it->wq; /* the candidates kept */
      return PETSC_FALSE;
    }
    *j = nb->cand[it->q++];
    if (it->wcand) it->wcand[it->wq] = *j;
    it->wq++;
    return PETSC_TRUE;
  }
  while (!it->bits) {
    if (++it->k >= it->nwr) { /* the next row */
      if (++it->r >= it->nr) return PETSC_FALSE;
      it->w += it->nwr;
      it->nwr = (it->len[it->r] + 63) / 64;
      it->k   = 0;
      if (!it->nwr) continue;
    }
    it->bits = it->w[it->k];
  }
  p       = 64 * it->k + __builtin_ctzll(it->bits);
  it->cur = it->bits & (~it->bits + 1); /* its bit, the lowest one left */
  it->bits ^= it->cur;
  *j = nb->order[it->q0[it->r] + p];
  return PETSC_TRUE;
}

/* the number of owned particle i's candidates */
static inline PetscInt FSNeighboursCandidateCount(const FSNeighbours *nb, PetscInt i)
{
  PetscInt nc = 0;
  if (nb->form == FS_CANDIDATES_INDICES) return nb->cend[i] - nb->cstart[i];
  for (PetscInt k = nb->cstart[i]; k < nb->cstart[i + 1]; k++) nc += __builtin_popcountll(nb->mask[k]);
  return nc;
}

/* removes the candidate FSNeighboursCandidateNext() returned last (e.g. a pair a wall cuts) */
static inline void FSNeighboursCandidateDrop(FSNeighbours *nb, FSCandidateIter *it)
{
  if (nb->form == FS_CANDIDATES_INDICES) {
    it->wcand = nb->cand;
    it->wend  = &nb->cend[it->i];
    it->wq--;
  } else it->w[it->k] &= ~it->cur;
  nb->ncand--;
}

/*
   Two reals in one vector register (GCC's vector extensions, which clang has too), for the pair loops: the two
   components of a vector get the same operations in the same order as a scalar loop's, so the results are the same
   bit for bit, in half the instructions. FS_HAVE_REAL2 says whether the compiler has them (else scalar code).
*/
#if defined(__GNUC__)
#  define FS_HAVE_REAL2 1
typedef double        FSReal2 __attribute__((vector_size(16)));
static inline FSReal2 FSLoad2(const PetscReal *p)
{
  FSReal2 v;
  memcpy(&v, p, sizeof(v));
  return v;
}
static inline void FSStore2(PetscReal *p, FSReal2 v) { memcpy(p, &v, sizeof(v)); }
#endif

/*
   FSNeighboursPick - the neighbours j != i of owned particle i within r^2 < R2 at the current positions
   (records rec with stride, position first), picked from its candidates: their indices into j[], x_j - x_i
   into dx[] (dim a pair) and r^2 into r2[]; returns their number (at most nb->maxcand, which bounds the
   arrays). With the candidates as bits, their indices first (integer work only, row by row), then their
   distances in a loop of their own, without branches on the distance: whether a candidate is inside is as good as
   random, and mispredicted branches cost more than the stores, so every candidate is written at the end of the arrays,
   which moves on only for those inside. Inlined, so that a caller with a constant dim gets the loop for its
   dimension.
*/
FS_ALWAYS_INLINE PetscInt FSNeighboursPick(const FSNeighbours *nb, const PetscInt dim, PetscInt i,
                                           const PetscReal rec[], PetscInt stride, PetscReal R2, PetscInt j[],
                                           PetscReal dx[], PetscReal r2[])
{
  const PetscReal *xi = &rec[i * stride];
  const PetscInt  *cj = j;
  PetscInt         nc, m = 0;

  if (nb->form == FS_CANDIDATES_INDICES) {
    cj = nb->cand + nb->cstart[i];
    nc = nb->cend[i] - nb->cstart[i];
  } else {
    const uint64_t *w = nb->mask + nb->cstart[i];
    PetscInt        q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS];
    const PetscInt  nr = FSNeighboursRows(nb, i, q0, len);
    nc                 = 0;
    for (PetscInt r = 0; r < nr; r++) {
      const PetscInt *base = nb->order + q0[r];
      const PetscInt  nwr  = (len[r] + 63) / 64;
      for (PetscInt k = 0; k < nwr; k++)
        for (uint64_t bits = w[k]; bits; bits &= bits - 1) j[nc++] = base[64 * k + __builtin_ctzll(bits)];
      w += nwr;
    }
  }
  { /* the write positions move on by whether the candidate is inside: pointers, not indices times dim */
    const PetscReal xi0 = xi[0], xi1 = xi[1], xi2 = dim == 3 ? xi[2] : 0;
    PetscReal      *dxm = dx, *r2m = r2;
    PetscInt       *jm = j;
    for (PetscInt q = 0; q < nc; q++) {
      const PetscInt   c  = cj[q];
      const PetscReal *xc = &rec[(ptrdiff_t)c * stride];
      const PetscReal  d0 = xc[0] - xi0, d1 = xc[1] - xi1;
      PetscReal        d2 = d0 * d0 + d1 * d1; /* = 0 + d0^2 + d1^2, the sum in the order of the components */
      PetscInt         in;
      dxm[0] = d0;
      dxm[1] = d1;
      if (dim == 3) {
        const PetscReal d3 = xc[2] - xi2;
        dxm[2]             = d3;
        d2 += d3 * d3;
      }
      *jm  = c;
      *r2m = d2;
      in   = d2 < R2;
      dxm += dim * in;
      r2m += in;
      jm += in;
      m += in;
    }
  }
  return m;
}
PETSC_INTERN PetscErrorCode FSNeighboursDestroy(FSNeighbours *);
