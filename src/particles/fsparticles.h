/*
   The particles' geometry (src/particles): the smoothing kernel, the decomposition of the domain over
   the ranks, the halo of ghost particles and the cell and neighbour lists. Plain data structures that
   know nothing of the solver: they take arrays of particle records.
*/
#pragma once
#include <flexslosh.h> /* FS_ALWAYS_INLINE */
#include <petscsf.h>

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

/* Cell-linked list (counting sort) and the candidate (Verlet) list of the owned particles (CSR). No list
   of the pairs within the support is kept: each pass over the pairs picks them from the candidates
   (FSNeighboursPick) as it visits them, which costs a distance per candidate and saves the list's memory. */
typedef struct {
  PetscInt  dim;
  PetscReal lo[3], cellsize;
  PetscInt  nc[3], ncells;
  PetscInt *cellstart; /* ncells+1 */
  PetscInt *cellof;    /* cell of each particle */
  PetscInt *order;     /* particles sorted by cell */
  PetscInt  ncap, ccap;
  /* candidate (Verlet) list, built when the lists are rebuilt */
  PetscInt  *cstart; /* nowned+1 */
  PetscInt  *cand;
  PetscInt   scap, ccandcap, ncand;
  PetscInt   maxcand; /* the most candidates of one particle */
  PetscInt64 npairs;  /* the pairs within the support at the last right-hand side (set by its pass) */
} FSNeighbours;

PETSC_INTERN PetscErrorCode FSNeighboursBuildCells(FSNeighbours *, PetscInt dim, PetscInt n, const PetscReal rec[],
                                                   PetscInt stride, PetscReal cellsize);
PETSC_INTERN PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *, PetscInt nowned, const PetscReal rec[],
                                                        PetscInt stride, PetscReal radius);

/*
   FSNeighboursPick - the neighbours j != i of owned particle i within r^2 < R2 at the current positions
   (records rec with stride, position first), picked from its candidates: their indices into j[], x_j - x_i
   into dx[] (dim a pair) and r^2 into r2[]; returns their number (at most nb->maxcand, which bounds the
   arrays). Without branches: whether a candidate is inside is as good as random, and mispredicted branches
   cost more than the stores, so every candidate is written at the end of the arrays, which moves on only
   for those inside. Inlined, so that a caller with a constant dim gets the loop for its dimension.
*/
FS_ALWAYS_INLINE PetscInt FSNeighboursPick(const FSNeighbours *nb, const PetscInt dim, PetscInt i,
                                           const PetscReal rec[], PetscInt stride, PetscReal R2, PetscInt j[],
                                           PetscReal dx[], PetscReal r2[])
{
  const PetscReal *xi = &rec[i * stride];
  const PetscInt  *c = nb->cand + nb->cstart[i], nc = nb->cstart[i + 1] - nb->cstart[i];
  PetscInt         m = 0;

  for (PetscInt q = 0; q < nc; q++) {
    const PetscInt   k  = c[q];
    const PetscReal *xk = &rec[k * stride];
    PetscReal        d2 = 0;
    for (PetscInt a = 0; a < dim; a++) {
      const PetscReal d = xk[a] - xi[a];
      dx[m * dim + a]   = d;
      d2 += d * d;
    }
    j[m]  = k;
    r2[m] = d2;
    m += d2 < R2;
  }
  return m;
}
PETSC_INTERN PetscErrorCode FSNeighboursDestroy(FSNeighbours *);
