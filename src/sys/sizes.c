/*
   The size checks of the set-up: a count of particles (a lattice's nx ny nz), counted in doubles before
   anything is allocated, against what an index can count and what the memory holds, so that a tiny
   -fs_dx (or a tank in millimetres read as metres) is an error that says what to do, not a 32-bit
   overflow that corrupts the heap or an allocation that swaps until the out-of-memory killer ends it.
*/
#include "sys/fssys.h"
#include <sys/resource.h>
#include <unistd.h>

/* the machine's physical memory in bytes (0 if unknown) */
static double PhysicalMemory(void)
{
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? (double)pages * (double)page : 0;
}

/* the memory the machine can give without swapping, in bytes: MemAvailable of /proc/meminfo (Linux: the free
   memory and the caches it can drop), else the physical memory; 0 if unknown */
static double AvailableMemory(void)
{
  FILE  *f = fopen("/proc/meminfo", "r");
  char   line[256];
  double avail = 0;

  if (f) {
    while (fgets(line, sizeof(line), f)) {
      long long kb;
      if (sscanf(line, "MemAvailable: %lld kB", &kb) == 1) {
        avail = 1024.0 * (double)kb;
        break;
      }
    }
    (void)fclose(f);
  }
  return avail > 0 ? avail : PhysicalMemory();
}

/* the least of mem (0: unknown) and the limits on this process's address space and data (ulimit -v, ulimit -d) */
static double LimitedMemory(double mem)
{
  const int     which[2] = {RLIMIT_AS, RLIMIT_DATA};
  struct rlimit rl;

  for (int k = 0; k < 2; k++)
    if (!getrlimit(which[k], &rl) && rl.rlim_cur != RLIM_INFINITY && (!mem || (double)rl.rlim_cur < mem))
      mem = (double)rl.rlim_cur;
  return mem;
}

/*
   FSMemoryTotal - the memory this process may use, in bytes (0 if unknown): the machine's physical
   memory, or less where a limit on the address space or the data segment (ulimit -v, ulimit -d) says
   so. The bound of the size checks, which stop a set-up whose arrays could never fit before it
   allocates them.
*/
double FSMemoryTotal(void) { return LimitedMemory(PhysicalMemory()); }

/*
   FSLatticeCount - the points of a lattice of spacing dx over a box of sides len[0..dim): the product
   of max(1, floor(len/dx + 1/2)), in a double (no overflow, and past 2^53 still a fair count for the
   checks).
*/
double FSLatticeCount(PetscInt dim, const PetscReal len[], PetscReal dx)
{
  double count = 1;

  for (PetscInt d = 0; d < dim; d++) count *= PetscMax(1.0, PetscFloorReal(len[d] / dx + 0.5));
  return count;
}

/*
   FSParticleBytes - the memory a particle takes in a run of dimension dim, in bytes: the marginal cost
   of a particle measured by bench/bench_memory.py (docs/performance.md, "bytes a particle": 2-D dam
   break 724-815, 3-D dam break 1915-1989, walls' lists included), rounded up; FS_PARTICLE_BYTES, the
   least, for another dim.
*/
double FSParticleBytes(PetscInt dim) { return dim == 3 ? 2000.0 : dim == 2 ? 850.0 : FS_PARTICLE_BYTES; }

/*
   FSParticleCountFits - whether count particles split over size ranks fit: FS_SIZE_INDEX where the
   count reaches PETSC_MAX_INT (the particles' ids and the global sizes are PetscInt) or a rank's share
   of the widest per-particle array (FS_PARTICLE_REALS reals) does; FS_SIZE_MEMORY where a rank's share
   at per bytes a particle (FSParticleBytes) is not below mem, the memory a rank may use (0: unknown,
   not checked). bytes: that share.
*/
FSSizeVerdict FSParticleCountFits(double count, PetscMPIInt size, double per, double mem, double *bytes)
{
  const double share = count / size;

  *bytes = share * per;
  if (!(count < PETSC_MAX_INT) || !(share * FS_PARTICLE_REALS < PETSC_MAX_INT)) return FS_SIZE_INDEX; /* and NaN */
  if (mem > 0 && !(*bytes < mem)) return FS_SIZE_MEMORY;
  return FS_SIZE_FITS;
}

/*
   FSCheckParticleCount - the shared size check of the fills: an error, before anything is allocated,
   where count particles (FSLatticeCount, or the liquid's volume over dx^dim) at -fs_dx dx would not fit
   (FSParticleCountFits at FSParticleBytes(dim) a particle on the ranks of comm, against a rank's share
   of its node's available memory or its own limit), naming -fs_dx, the count, the memory a rank would
   need and what to do. region says which liquid and walls the count is of, to start the message;
   advice (NULL: the coordinates' unit in general) how to check the geometry's unit.

   Collective

   Level: developer

.seealso: FSLatticeCount(), FSParticleCountFits()
*/
PetscErrorCode FSCheckParticleCount(MPI_Comm comm, PetscInt dim, PetscReal dx, double count, const char region[],
                                    const char advice[])
{
  const double  per = FSParticleBytes(dim);
  const double  GB  = 1024.0 * 1024.0 * 1024.0;
  PetscMPIInt   size;
  double        mem, bytes;
  FSSizeVerdict v;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  { /* the ranks of a node share its memory */
    MPI_Comm    node;
    PetscMPIInt nodesize;
    PetscCallMPI(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
    PetscCallMPI(MPI_Comm_size(node, &nodesize));
    PetscCallMPI(MPI_Comm_free(&node));
    mem = LimitedMemory(AvailableMemory() / nodesize);
    /* one verdict for all ranks; 0, unknown, is no bound */
    if (!mem) mem = PETSC_MAX_REAL;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &mem, 1, MPI_DOUBLE, MPI_MIN, comm));
    if (mem == PETSC_MAX_REAL) mem = 0;
  }
  v = FSParticleCountFits(count, size, per, mem, &bytes);
  if (!advice) advice = "check the coordinates (in metres)";
  PetscCheck(v != FS_SIZE_INDEX, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g would make %.3g particles (at least %.3g GB on each of the %d rank(s)), more than an index "
             "can count (%s): %s, or %s",
             region, (double)dx, count, bytes / GB, size,
             count < PETSC_MAX_INT ? "a rank's particles and ghosts" : "the particles' ids are PetscInt",
             count < PETSC_MAX_INT ? "use more ranks or a coarser -fs_dx" : "use a coarser -fs_dx", advice);
  PetscCheck(v != FS_SIZE_MEMORY, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g would make %.3g particles, needing at least %.3g GB on each of the %d rank(s) (%d bytes a "
             "particle in %" PetscInt_FMT "-D, measured), more than the %.3g GB a rank may use (its share of the "
             "node's available memory, or ulimit -v): use a coarser -fs_dx or more ranks (on more nodes), or %s",
             region, (double)dx, count, bytes / GB, size, (int)per, dim, mem / GB, advice);
  PetscFunctionReturn(0);
}
