/*
   Unit tests of the size checks (src/sys/sizes.c):
   - FSLatticeCount: the lattice's points, past 2^31 without overflow, at least 1 a direction;
   - FSParticleCountFits: the index bounds (the ids, a rank's widest array), the memory bound, NaN;
   - FSCheckParticleCount: no error for a small count; errors naming -fs_dx, the count and what to do
     past an index and, under a 4 GB address-space limit (ulimit -v), past the memory.
*/
#include <math.h>
#include <string.h>
#include <sys/resource.h>
#include "sys/fssys.h"
#include "../errorcapture.h"

#define CHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_sizes: " __VA_ARGS__)

/* FSCheckParticleCount(count) must fail with a message holding each of must[] (NULL-terminated) */
static PetscErrorCode ExpectError(double count, const char *must[])
{
  ErrorText      e = {""};
  PetscErrorCode ierr;

  PetscFunctionBegin;
  FS_TEST_CAPTURE(FSCheckParticleCount(PETSC_COMM_SELF, 3, 0.001, count, "the box", NULL), e, ierr);
  CHECK(ierr == PETSC_ERR_ARG_OUTOFRANGE, "%g particles must be an error", count);
  for (PetscInt k = 0; must[k]; k++)
    CHECK(strstr(e.text, must[k]), "the error must say \"%s\": \"%s\"", must[k], e.text);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  const PetscReal big[3] = {4.1, 1.024, 1.024}, small[2] = {1, 0.5}, thin[3] = {1, 1e-6, 1};
  double          bytes;
  struct rlimit   saved, four;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  CHECK(FSLatticeCount(2, small, 0.1) == 50, "1 x 0.5 at 0.1: %g points", FSLatticeCount(2, small, 0.1));
  CHECK(FSLatticeCount(3, big, 0.001) == 4100.0 * 1024 * 1024, "%g points", FSLatticeCount(3, big, 0.001));
  CHECK(FSLatticeCount(3, thin, 0.1) == 100, "a side below dx counts 1: %g points", FSLatticeCount(3, thin, 0.1));

  CHECK(FSParticleCountFits(1000, 1, FS_PARTICLE_BYTES, 0, &bytes) == FS_SIZE_FITS && bytes == 1000 * FS_PARTICLE_BYTES,
        "1000 fit");
  CHECK(FSParticleCountFits(1000, 1, FS_PARTICLE_BYTES, 2e6, &bytes) == FS_SIZE_FITS, "1000 fit in 2 MB");
  CHECK(FSParticleCountFits(1000, 1, FS_PARTICLE_BYTES, 1e6, &bytes) == FS_SIZE_MEMORY, "1000 do not fit in 1 MB");
  CHECK(FSParticleCountFits(2000, 2, FS_PARTICLE_BYTES, 1.5e6, &bytes) == FS_SIZE_FITS &&
            bytes == 1000 * FS_PARTICLE_BYTES,
        "2000 on 2 ranks fit in 1.5 MB a rank");
  CHECK(FSParticleCountFits(PETSC_MAX_INT, 1000, FS_PARTICLE_BYTES, 0, &bytes) == FS_SIZE_INDEX,
        "the ids reach PETSC_MAX_INT");
  CHECK(FSParticleCountFits(4100.0 * 1024 * 1024, 1, FS_PARTICLE_BYTES, 0, &bytes) == FS_SIZE_INDEX,
        "the ids overflow");
  CHECK(FSParticleCountFits(PETSC_MAX_INT / 8.0, 1, FS_PARTICLE_BYTES, 0, &bytes) == FS_SIZE_INDEX,
        "a rank's records overflow");
  CHECK(FSParticleCountFits(PETSC_MAX_INT / 8.0, 8, FS_PARTICLE_BYTES, 0, &bytes) == FS_SIZE_FITS,
        "8 ranks share them");
  CHECK(FSParticleCountFits(NAN, 1, FS_PARTICLE_BYTES, 0, &bytes) == FS_SIZE_INDEX, "NaN is no count");

  PetscCall(FSCheckParticleCount(PETSC_COMM_SELF, 3, 0.001, 1000, "the box", NULL));
  {
    const char *must[] = {"the box: -fs_dx 0.001 would make 4.3e+09 particles", "GB", "use a coarser -fs_dx", NULL};
    PetscCall(ExpectError(4100.0 * 1024 * 1024, must));
  }
  {
    const char *must[] = {"the box: -fs_dx 0.001 would make 1e+08 particles",
                          "186 GB",
                          "2000 bytes a particle in 3-D",
                          "3.81 GB",
                          "use a coarser -fs_dx or more ranks",
                          NULL};
    CHECK(!getrlimit(RLIMIT_AS, &saved), "getrlimit");
    four          = saved;
    four.rlim_cur = 4000000 * (rlim_t)1024;
    CHECK(!setrlimit(RLIMIT_AS, &four), "setrlimit");
    PetscCall(ExpectError(1e8, must));
    CHECK(!setrlimit(RLIMIT_AS, &saved), "setrlimit back");
  }
  PetscCall(PetscFinalize());
  return 0;
}
