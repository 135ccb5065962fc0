/*
   Halo exchange: ghost copies of the particles of neighbouring subdomains (and periodic images).

   FSHaloBuild selects, after each migration, the owned particles within the halo width of a face,
   edge or corner of this rank's box and sends one copy per neighbouring rank (shifted by the
   period across a periodic boundary; a rank may be its own neighbour). The result is a PetscSF
   whose roots are the owned particle records and whose leaves are the ghost records stored after
   them in the same array, so a refresh is one PetscSFBcast.
*/
#include "particles/fsparticles.h"

static PetscErrorCode FSHaloPushSend(FSHalo *hl, PetscInt dim, PetscMPIInt rank, PetscInt index,
                                     const PetscReal shift[])
{
  PetscFunctionBegin;
  if (hl->nsend == hl->sendcap) {
    PetscInt     cap = PetscMax(1024, 2 * hl->sendcap);
    PetscInt    *idx;
    PetscMPIInt *rk;
    PetscReal   *sh;
    PetscCall(PetscMalloc3(cap, &idx, cap, &rk, cap * dim, &sh));
    PetscCall(PetscArraycpy(idx, hl->send_index, hl->nsend));
    PetscCall(PetscArraycpy(rk, hl->send_rank, hl->nsend));
    PetscCall(PetscArraycpy(sh, hl->send_shift, hl->nsend * dim));
    PetscCall(PetscFree3(hl->send_index, hl->send_rank, hl->send_shift));
    hl->send_index = idx;
    hl->send_rank  = rk;
    hl->send_shift = sh;
    hl->sendcap    = cap;
  }
  hl->send_index[hl->nsend] = index;
  hl->send_rank[hl->nsend]  = rank;
  for (PetscInt d = 0; d < dim; d++) hl->send_shift[hl->nsend * dim + d] = shift[d];
  hl->nsend++;
  PetscFunctionReturn(0);
}

/* FSHaloFindSends - the owned particles within width of this rank's subdomain faces, each with every
   neighbouring rank (and periodic shift) that needs a copy of it */
static PetscErrorCode FSHaloFindSends(FSHalo *hl, const FSDecomp *dd, PetscInt nowned, const PetscReal rec[],
                                      PetscInt stride, PetscReal width)
{
  const PetscInt dim = dd->dim, noff = dim == 2 ? 9 : 27;

  PetscFunctionBegin;
  hl->nsend = 0;
  for (PetscInt p = 0; p < nowned; p++) {
    const PetscReal *x = &rec[p * stride];
    PetscBool        low[3], high[3];
    for (PetscInt d = 0; d < dim; d++) {
      low[d]  = (PetscBool)(x[d] - dd->cut[d][dd->coord[d]] < width);
      high[d] = (PetscBool)(dd->cut[d][dd->coord[d] + 1] - x[d] < width);
    }
    if (dim == 2 && !(low[0] || low[1] || high[0] || high[1])) continue;
    if (dim == 3 && !(low[0] || low[1] || low[2] || high[0] || high[1] || high[2])) continue;
    for (PetscInt o = 0; o < noff; o++) {
      PetscInt    off[3]   = {o % 3 - 1, (o / 3) % 3 - 1, o / 9 - 1};
      PetscMPIInt t[3]     = {0, 0, 0};
      PetscReal   shift[3] = {0, 0, 0};
      PetscBool   use = PETSC_TRUE, any = PETSC_FALSE;
      for (PetscInt d = 0; d < dim && use; d++) {
        t[d] = dd->coord[d] + (PetscMPIInt)off[d];
        if (off[d] == 0) continue;
        any = PETSC_TRUE;
        if ((off[d] < 0 && !low[d]) || (off[d] > 0 && !high[d])) use = PETSC_FALSE;
        else if (t[d] < 0) {
          if (dd->periodic[d]) {
            t[d] += dd->np[d];
            shift[d] = dd->len[d];
          } else use = PETSC_FALSE;
        } else if (t[d] >= dd->np[d]) {
          if (dd->periodic[d]) {
            t[d] -= dd->np[d];
            shift[d] = -dd->len[d];
          } else use = PETSC_FALSE;
        }
      }
      if (!use || !any) continue;
      PetscCall(FSHaloPushSend(hl, dim, FSDecompRankAt(dd, t), p, shift));
    }
  }

  PetscFunctionReturn(0);
}

/* FSHaloSetTypes - the MPI datatypes of a particle record (stride reals) and of its first-pass quantities (dim + 1) */
static PetscErrorCode FSHaloSetTypes(FSHalo *hl, PetscInt dim, PetscInt stride)
{
  PetscFunctionBegin;
  if (hl->rectype == MPI_DATATYPE_NULL || hl->recstride != stride) {
    if (hl->rectype != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&hl->rectype));
    PetscCallMPI(MPI_Type_contiguous((PetscMPIInt)stride, MPIU_REAL, &hl->rectype));
    PetscCallMPI(MPI_Type_commit(&hl->rectype));
    hl->recstride = stride;
  }
  if (hl->auxtype == MPI_DATATYPE_NULL) {
    hl->auxstride = dim + 1;
    PetscCallMPI(MPI_Type_contiguous((PetscMPIInt)hl->auxstride, MPIU_REAL, &hl->auxtype));
    PetscCallMPI(MPI_Type_commit(&hl->auxtype));
  }
  PetscFunctionReturn(0);
}

/*
   FSHaloBuild - finds the ghosts of every rank and sets up the PetscSF that refreshes them.

   Input Parameters:
+  comm   - the run's communicator
.  dd     - the decomposition
.  nowned - number of owned particles
.  rec    - owned particle records (position first)
.  stride - reals per record
-  width  - halo width (kernel support plus skin)

   Notes: collective. Ghost order is deterministic (by source rank, then source order).
*/
PetscErrorCode FSHaloBuild(FSHalo *hl, MPI_Comm comm, const FSDecomp *dd, PetscInt nowned, const PetscReal rec[],
                           PetscInt stride, PetscReal width)
{
  const PetscInt dim  = dd->dim;
  PetscMPIInt    size = dd->size, nto = 0, nfrom = 0, *toranks, *fromranks = NULL;
  PetscInt      *counts, *todata, *fromdata = NULL, *perm, *order;
  PetscReal     *sendbuf, *recvbuf;
  PetscSFNode   *remote;
  PetscInt      *ilocal, nrec = 1 + dim;

  PetscFunctionBegin;
  PetscCall(FSHaloFindSends(hl, dd, nowned, rec, stride, width));

  /* order the sends by destination rank (counting sort, stable) */
  PetscCall(PetscCalloc1(size + 1, &counts));
  for (PetscInt k = 0; k < hl->nsend; k++) counts[hl->send_rank[k] + 1]++;
  for (PetscMPIInt r = 0; r < size; r++) counts[r + 1] += counts[r];
  PetscCall(PetscMalloc2(hl->nsend, &perm, hl->nsend * nrec, &sendbuf));
  for (PetscInt k = 0; k < hl->nsend; k++) perm[counts[hl->send_rank[k]]++] = k;
  for (PetscMPIInt r = size; r > 0; r--) counts[r] = counts[r - 1];
  counts[0] = 0;
  for (PetscInt k = 0; k < hl->nsend; k++) {
    PetscInt q        = perm[k];
    sendbuf[k * nrec] = (PetscReal)hl->send_index[q];
    for (PetscInt d = 0; d < dim; d++) sendbuf[k * nrec + 1 + d] = hl->send_shift[q * dim + d];
  }
  for (PetscMPIInt r = 0; r < size; r++)
    if (counts[r + 1] > counts[r]) nto++;
  /* what each refresh sends to other ranks (the copies a rank keeps of its own are no messages) */
  hl->nsendranks  = 0;
  hl->nsendremote = 0;
  for (PetscMPIInt r = 0; r < size; r++)
    if (r != dd->rank && counts[r + 1] > counts[r]) {
      hl->nsendranks++;
      hl->nsendremote += counts[r + 1] - counts[r];
    }
  /* the build's messages: the handshake (two ints to each destination) and the ghosts' addresses and shifts */
  hl->build_msgs += 2 * hl->nsendranks;
  hl->build_bytes += (PetscLogDouble)hl->nsendranks * 2 * sizeof(PetscInt) +
                     (PetscLogDouble)hl->nsendremote * nrec * sizeof(PetscReal);
  hl->nbuilds++;
  PetscCall(PetscMalloc2(nto, &toranks, 2 * nto, &todata));
  nto = 0;
  for (PetscMPIInt r = 0; r < size; r++)
    if (counts[r + 1] > counts[r]) {
      toranks[nto]        = r;
      todata[2 * nto]     = counts[r + 1] - counts[r];
      todata[2 * nto + 1] = counts[r];
      nto++;
    }
  PetscCall(PetscCommBuildTwoSided(comm, 2, MPIU_INT, nto, toranks, todata, &nfrom, &fromranks, &fromdata));

  /* receive side: ghosts ordered by source rank */
  PetscCall(PetscMalloc1(nfrom, &order));
  for (PetscMPIInt k = 0; k < nfrom; k++) order[k] = k;
  for (PetscMPIInt a = 1; a < nfrom; a++) { /* insertion sort: few neighbours */
    PetscInt v = order[a], b = a - 1;
    while (b >= 0 && fromranks[order[b]] > fromranks[v]) {
      order[b + 1] = order[b];
      b--;
    }
    order[b + 1] = v;
  }
  hl->nghost = 0;
  for (PetscMPIInt k = 0; k < nfrom; k++) hl->nghost += fromdata[2 * k];
  PetscCall(PetscMalloc3(hl->nghost, &remote, hl->nghost, &ilocal, hl->nghost * nrec, &recvbuf));
  {
    PetscInt g = 0;
    for (PetscMPIInt a = 0; a < nfrom; a++) {
      PetscMPIInt k = (PetscMPIInt)order[a];
      for (PetscInt m = 0; m < fromdata[2 * k]; m++, g++) {
        remote[g].rank  = fromranks[k];
        remote[g].index = fromdata[2 * k + 1] + m;
      }
    }
  }
  { /* each ghost's source index and shift, by messages to and from the ranks the handshake found (a PetscSF would
       take a collective of its own to find them again) */
    MPI_Comm     icomm;
    PetscMPIInt  tag;
    MPI_Request *req;
    PetscInt     g = 0;
    PetscCall(PetscCommDuplicate(comm, &icomm, &tag));
    PetscCall(PetscMalloc1(nfrom + nto, &req));
    for (PetscMPIInt a = 0; a < nfrom; a++) { /* the ghosts by source rank, each source's in its order */
      PetscMPIInt k = (PetscMPIInt)order[a];
      PetscCallMPI(MPI_Irecv(&recvbuf[g * nrec], (PetscMPIInt)(fromdata[2 * k] * nrec), MPIU_REAL, fromranks[k], tag,
                             icomm, &req[a]));
      g += fromdata[2 * k];
    }
    for (PetscMPIInt k = 0; k < nto; k++)
      PetscCallMPI(MPI_Isend(&sendbuf[todata[2 * k + 1] * nrec], (PetscMPIInt)(todata[2 * k] * nrec), MPIU_REAL,
                             toranks[k], tag, icomm, &req[nfrom + k]));
    PetscCallMPI(MPI_Waitall(nfrom + nto, req, MPI_STATUSES_IGNORE));
    PetscCall(PetscFree(req));
    PetscCall(PetscCommDestroy(&icomm));
  }

  /* the refresh SF: leaf g (record nowned+g) <- root (source rank, source index) */
  if (hl->nghost > hl->cap) {
    PetscCall(PetscFree(hl->shift));
    hl->cap = PetscMax(hl->nghost, 2 * hl->cap);
    PetscCall(PetscMalloc1(hl->cap * dim, &hl->shift));
  }
  for (PetscInt g = 0; g < hl->nghost; g++) {
    remote[g].index = (PetscInt)recvbuf[g * nrec];
    ilocal[g]       = nowned + g;
    for (PetscInt d = 0; d < dim; d++) hl->shift[g * dim + d] = recvbuf[g * nrec + 1 + d];
  }
  PetscCall(PetscSFDestroy(&hl->sf));
  PetscCall(PetscSFCreate(comm, &hl->sf));
  PetscCall(PetscSFSetGraph(hl->sf, nowned, hl->nghost, ilocal, PETSC_COPY_VALUES, remote, PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(hl->sf));
  PetscCall(FSHaloSetTypes(hl, dim, stride));
  PetscCall(PetscFree3(remote, ilocal, recvbuf));
  PetscCall(PetscFree(order));
  PetscCall(PetscFree(fromranks));
  PetscCall(PetscFree(fromdata));
  PetscCall(PetscFree2(toranks, todata));
  PetscCall(PetscFree2(perm, sendbuf));
  PetscCall(PetscFree(counts));
  PetscFunctionReturn(0);
}

/* a refresh of count reals a particle from the owners to the ghosts (unit: their MPI type), counted in the
   run's statistics; the ghosts' values are ready after FSHaloBcastEnd */
static PetscErrorCode FSHaloBcastBegin(FSHalo *hl, MPI_Datatype unit, PetscInt count, PetscReal a[])
{
  PetscFunctionBegin;
  hl->refresh_msgs += hl->nsendranks;
  hl->refresh_bytes += (PetscLogDouble)hl->nsendremote * count * sizeof(PetscReal);
  PetscCall(PetscSFBcastBegin(hl->sf, unit, a, a, MPI_REPLACE));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSHaloBcastEnd(FSHalo *hl, MPI_Datatype unit, PetscReal a[])
{
  PetscFunctionBegin;
  PetscCall(PetscSFBcastEnd(hl->sf, unit, a, a, MPI_REPLACE));
  PetscFunctionReturn(0);
}

/*
   FSHaloRefreshBegin/End - copies the owners' current records into the ghost records and applies the periodic
   shifts. Between the two the owned records may be read but not changed, and the ghosts' are not ready: work
   on the owned particles alone can go on while the messages travel. FSHaloRefresh does both.
*/
PetscErrorCode FSHaloRefreshBegin(FSHalo *hl, PetscReal rec[])
{
  return FSHaloBcastBegin(hl, hl->rectype, hl->recstride, rec);
}

PetscErrorCode FSHaloRefreshEnd(FSHalo *hl, PetscInt dim, PetscInt nowned, PetscReal rec[])
{
  PetscFunctionBegin;
  PetscCall(FSHaloBcastEnd(hl, hl->rectype, rec));
  for (PetscInt g = 0; g < hl->nghost; g++) {
    PetscReal *x = &rec[(nowned + g) * hl->recstride];
    for (PetscInt d = 0; d < dim; d++) x[d] += hl->shift[g * dim + d];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FSHaloRefresh(FSHalo *hl, PetscInt dim, PetscInt nowned, PetscReal rec[])
{
  PetscFunctionBegin;
  PetscCall(FSHaloRefreshBegin(hl, rec));
  PetscCall(FSHaloRefreshEnd(hl, dim, nowned, rec));
  PetscFunctionReturn(0);
}

/* FSHaloRefreshAuxBegin/End - copies the owners' derived quantities (density gradient, ||D||) to the ghosts, as
   FSHaloRefreshBegin/End; FSHaloRefreshAux does both. */
PetscErrorCode FSHaloRefreshAuxBegin(FSHalo *hl, PetscReal aux[])
{
  return FSHaloBcastBegin(hl, hl->auxtype, hl->auxstride, aux);
}

PetscErrorCode FSHaloRefreshAuxEnd(FSHalo *hl, PetscReal aux[]) { return FSHaloBcastEnd(hl, hl->auxtype, aux); }

PetscErrorCode FSHaloRefreshAux(FSHalo *hl, PetscReal aux[])
{
  PetscFunctionBegin;
  PetscCall(FSHaloRefreshAuxBegin(hl, aux));
  PetscCall(FSHaloRefreshAuxEnd(hl, aux));
  PetscFunctionReturn(0);
}

/* FSHaloRefreshScalarBegin/End - copies one real per particle (e.g. the Shepard factor) from the owners to the
   ghosts, as FSHaloRefreshBegin/End; FSHaloRefreshScalar does both. */
PetscErrorCode FSHaloRefreshScalarBegin(FSHalo *hl, PetscReal a[]) { return FSHaloBcastBegin(hl, MPIU_REAL, 1, a); }

PetscErrorCode FSHaloRefreshScalarEnd(FSHalo *hl, PetscReal a[]) { return FSHaloBcastEnd(hl, MPIU_REAL, a); }

PetscErrorCode FSHaloRefreshScalar(FSHalo *hl, PetscReal a[])
{
  PetscFunctionBegin;
  PetscCall(FSHaloRefreshScalarBegin(hl, a));
  PetscCall(FSHaloRefreshScalarEnd(hl, a));
  PetscFunctionReturn(0);
}

PetscErrorCode FSHaloDestroy(FSHalo *hl)
{
  PetscFunctionBegin;
  PetscCall(PetscSFDestroy(&hl->sf));
  PetscCall(PetscFree(hl->shift));
  PetscCall(PetscFree3(hl->send_index, hl->send_rank, hl->send_shift));
  if (hl->rectype != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&hl->rectype));
  if (hl->auxtype != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&hl->auxtype));
  PetscFunctionReturn(0);
}
