/*
   Numeric options checked where they are read: FSOptionsReal(), FSOptionsInt() and
   FSOptionsRealArray() read an option as PetscOptionsReal() etc. do, then refuse a value that is not
   a number, NaN, Inf or outside the option's range with an error naming the option, the value and
   the range. The range is also appended to the option's -help text.
*/
#include "sys/fssys.h"
#include <errno.h>

/* Num - a number as C prints it with %g ("1", "0.5", "1e+300", "nan"; PETSc's own %g adds a dot to "1."). */
static void Num(PetscReal v, char buf[], size_t len) { snprintf(buf, len, "%g", (double)v); }

/* OpenEnds - which bounds of the range are open */
static void OpenEnds(FSRange range, PetscBool *openlo, PetscBool *openhi)
{
  *openlo = (PetscBool)(range == FS_RANGE_OPEN_LOWER || range == FS_RANGE_OPEN);
  *openhi = (PetscBool)(range == FS_RANGE_OPEN_UPPER || range == FS_RANGE_OPEN);
}

/* RangeText - the range in words ("a positive number", "a number in [0, 1)", "at least 1", "2 or 3"). */
static PetscErrorCode RangeText(PetscReal lo, PetscReal hi, FSRange range, PetscBool isint, char text[], size_t len)
{
  const PetscBool haslo = lo > PETSC_NINFINITY ? PETSC_TRUE : PETSC_FALSE,
                  hashi = hi < PETSC_INFINITY ? PETSC_TRUE : PETSC_FALSE;
  PetscBool openlo, openhi;
  char      l[32], h[32];

  PetscFunctionBegin;
  OpenEnds(range, &openlo, &openhi);
  Num(lo, l, sizeof(l));
  Num(hi, h, sizeof(h));
  if (isint) {
    if (haslo && hashi && hi == lo + 1) PetscCall(PetscSNPrintf(text, len, "%s or %s", l, h));
    else if (haslo && hashi) PetscCall(PetscSNPrintf(text, len, "an integer in [%s, %s]", l, h));
    else if (haslo) PetscCall(PetscSNPrintf(text, len, "at least %s", l));
    else if (hashi) PetscCall(PetscSNPrintf(text, len, "at most %s", h));
    else PetscCall(PetscSNPrintf(text, len, "an integer"));
  } else if (haslo && hashi) {
    PetscCall(PetscSNPrintf(text, len, "a number in %s%s, %s%s", openlo ? "(" : "[", l, h, openhi ? ")" : "]"));
  } else if (haslo && lo == 0) {
    PetscCall(PetscSNPrintf(text, len, openlo ? "a positive number" : "a non-negative number"));
  } else if (haslo) {
    PetscCall(PetscSNPrintf(text, len, "a number %s %s", openlo ? ">" : ">=", l));
  } else if (hashi) {
    PetscCall(PetscSNPrintf(text, len, "a number %s %s", openhi ? "<" : "<=", h));
  } else PetscCall(PetscSNPrintf(text, len, "a finite number"));
  PetscFunctionReturn(0);
}

/* InRange - v is finite and within the range. */
static PetscBool InRange(PetscReal v, PetscReal lo, PetscReal hi, FSRange range)
{
  PetscBool openlo, openhi;

  OpenEnds(range, &openlo, &openhi);
  if (PetscIsInfOrNanReal(v)) return PETSC_FALSE;
  if (lo > PETSC_NINFINITY && (openlo ? !(v > lo) : !(v >= lo))) return PETSC_FALSE;
  if (hi < PETSC_INFINITY && (openhi ? !(v < hi) : !(v <= hi))) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* RawValue - the option's text as given (set is false when absent or given without a value). */
static PetscErrorCode RawValue(PetscOptionItems *items, const char opt[], char raw[], size_t len, PetscBool *set)
{
  PetscFunctionBegin;
  raw[0] = 0;
  PetscCall(PetscOptionsGetString(items->options, items->prefix, opt, raw, len, set));
  if (*set && !raw[0]) *set = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*
   FSOptionsReal - reads a real option as PetscOptionsReal() does, and checks it: a value that is not a
   number, NaN, Inf or outside the range is an error (PETSC_ERR_ARG_OUTOFRANGE) naming the option, the
   value and the range.

   Collective (an error on every rank of the options block's communicator)

   Input Parameters:
+  items  - the options block (PetscOptionsObject inside PetscOptionsBegin()/End())
.  opt    - the option, "-fs_..."
.  text   - its help text (the range is appended to it)
.  man    - its manual page
.  lo, hi - the bounds (PETSC_NINFINITY, PETSC_INFINITY: none; Inf and NaN are refused in any case)
-  range  - which bounds are open: FS_RANGE_CLOSED, FS_RANGE_OPEN_LOWER, FS_RANGE_OPEN_UPPER, FS_RANGE_OPEN

   Input/Output Parameter:
.  value - in: the current value (the default), out: the option's value if given

   Output Parameter:
.  set - whether the option was given (may be NULL)

   Note: only a given value is checked; the default is the caller's (it may lie outside, e.g. 0 for
   "from the case" where the range excludes 0).

.seealso: FSOptionsInt(), FSOptionsRealArray()
*/
PetscErrorCode FSOptionsReal(PetscOptionItems *items, const char opt[], const char text[], const char man[],
                             PetscReal *value, PetscBool *set, PetscReal lo, PetscReal hi, FSRange range)
{
  char      help[512], desc[128], raw[256];
  PetscBool given;

  PetscFunctionBegin;
  PetscCall(RangeText(lo, hi, range, PETSC_FALSE, desc, sizeof(desc)));
  PetscCall(PetscSNPrintf(help, sizeof(help), "%s (%s)", text, desc));
  PetscCall(RawValue(items, opt, raw, sizeof(raw), &given));
  if (given) {
    char *end;
    (void)strtod(raw, &end);
    PetscCheck(end != raw && !*end, items->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s %s is not a number: expected %s", opt,
               raw, desc);
  }
  PetscCall(PetscOptionsReal_Private(items, opt, help, man, *value, value, &given));
  if (given && !InRange(*value, lo, hi, range)) {
    char num[32];
    Num(*value, num, sizeof(num));
    SETERRQ(items->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s %s is out of range: expected %s", opt, num, desc);
  }
  if (set) *set = given;
  PetscFunctionReturn(0);
}

/* CheckIntText - raw, an integer option's value as given, is an integer in [lo, hi]; else an error naming the option,
   the value and the range (desc). PETSc's own parsing would keep the low bits of a value beyond the PetscInt range. */
static PetscErrorCode CheckIntText(MPI_Comm comm, const char opt[], const char raw[], PetscInt lo, PetscInt hi,
                                   const char desc[])
{
  char     *end;
  long long v;

  PetscFunctionBegin;
  errno = 0;
  v     = strtoll(raw, &end, 10);
  PetscCheck(end != raw && !*end, comm, PETSC_ERR_ARG_OUTOFRANGE, "%s %s is not an integer: expected %s", opt, raw,
             desc);
  PetscCheck(errno != ERANGE && v >= lo && v <= hi, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s %s is out of range: expected %s", opt, raw, desc);
  PetscFunctionReturn(0);
}

/*
   FSOptionsCheckPetscInt - checks an integer option that PETSc reads itself (TSSetFromOptions() reads -ts_max_steps),
   before it does, as FSOptionsInt() checks flexslosh's: a value that is not an integer, does not fit a PetscInt or lies
   outside [lo, hi] is an error naming the option, the value and the range (PETSc would keep the value's low 32 bits:
   -ts_max_steps 4294967297 ran one step). Nothing happens when the option is not given.

   Collective

   Input Parameters:
+  comm   - the communicator of the object that reads the option
.  opt    - the option, e.g. "-ts_max_steps" (no prefix)
-  lo, hi - the closed bounds (PETSC_MIN_INT, PETSC_MAX_INT: none)
*/
PetscErrorCode FSOptionsCheckPetscInt(MPI_Comm comm, const char opt[], PetscInt lo, PetscInt hi)
{
  char      raw[256], desc[128];
  PetscBool given;

  PetscFunctionBegin;
  PetscCall(PetscOptionsGetString(NULL, NULL, opt, raw, sizeof(raw), &given));
  if (!given || !raw[0]) PetscFunctionReturn(0);
  PetscCall(RangeText(lo > PETSC_MIN_INT ? (PetscReal)lo : PETSC_NINFINITY,
                      hi < PETSC_MAX_INT ? (PetscReal)hi : PETSC_INFINITY, FS_RANGE_CLOSED, PETSC_TRUE, desc,
                      sizeof(desc)));
  PetscCall(CheckIntText(comm, opt, raw, lo, hi, desc));
  PetscFunctionReturn(0);
}

/*
   FSOptionsInt - reads an integer option as PetscOptionsInt() does, and checks it: a value that is
   not an integer, does not fit a PetscInt or lies outside [lo, hi] is an error naming the option,
   the value and the range.

   Collective (an error on every rank of the options block's communicator)

   Input Parameters:
+  items  - the options block (PetscOptionsObject)
.  opt    - the option, "-fs_..."
.  text   - its help text (the range is appended to it)
.  man    - its manual page
-  lo, hi - the closed bounds (PETSC_MIN_INT, PETSC_MAX_INT: none)

   Input/Output Parameter:
.  value - in: the current value (the default), out: the option's value if given

   Output Parameter:
.  set - whether the option was given (may be NULL)

.seealso: FSOptionsReal(), FSOptionsRealArray()
*/
PetscErrorCode FSOptionsInt(PetscOptionItems *items, const char opt[], const char text[], const char man[],
                            PetscInt *value, PetscBool *set, PetscInt lo, PetscInt hi)
{
  char      help[512], desc[128], raw[256];
  PetscBool given;

  PetscFunctionBegin;
  PetscCall(RangeText(lo > PETSC_MIN_INT ? (PetscReal)lo : PETSC_NINFINITY,
                      hi < PETSC_MAX_INT ? (PetscReal)hi : PETSC_INFINITY, FS_RANGE_CLOSED, PETSC_TRUE, desc,
                      sizeof(desc)));
  PetscCall(PetscSNPrintf(help, sizeof(help), "%s (%s)", text, desc));
  PetscCall(RawValue(items, opt, raw, sizeof(raw), &given));
  if (given) PetscCall(CheckIntText(items->comm, opt, raw, lo, hi, desc));
  PetscCall(PetscOptionsInt_Private(items, opt, help, man, *value, value, &given, PETSC_MIN_INT, PETSC_MAX_INT));
  if (set) *set = given;
  PetscFunctionReturn(0);
}

/*
   FSOptionsRealArray - reads a list of reals as PetscOptionsRealArray() does, and checks each
   component as FSOptionsReal() checks a value: an error names the option, the component, its value
   and the range. The number of values is the caller's to check.

   Collective (an error on every rank of the options block's communicator)

   Input Parameters:
+  items  - the options block (PetscOptionsObject)
.  opt    - the option, "-fs_..."
.  text   - its help text (the range is appended to it)
.  man    - its manual page
.  lo, hi - the bounds of every component (PETSC_NINFINITY, PETSC_INFINITY: none)
-  range  - which bounds are open (FSRange)

   Input/Output Parameters:
+  v - in: the current values, out: the option's values if given
-  n - in: the room in v, out: the number of values given

   Output Parameter:
.  set - whether the option was given (may be NULL)

.seealso: FSOptionsReal(), FSOptionsInt()
*/
PetscErrorCode FSOptionsRealArray(PetscOptionItems *items, const char opt[], const char text[], const char man[],
                                  PetscReal v[], PetscInt *n, PetscBool *set, PetscReal lo, PetscReal hi, FSRange range)
{
  char      help[512], desc[128];
  PetscBool given = PETSC_FALSE;

  PetscFunctionBegin;
  PetscCall(RangeText(lo, hi, range, PETSC_FALSE, desc, sizeof(desc)));
  PetscCall(PetscSNPrintf(help, sizeof(help), "%s (each %s)", text, desc));
  PetscCall(PetscOptionsRealArray_Private(items, opt, help, man, v, n, &given));
  for (PetscInt i = 0; given && i < *n; i++) {
    char num[32];
    if (InRange(v[i], lo, hi, range)) continue;
    Num(v[i], num, sizeof(num));
    SETERRQ(items->comm, PETSC_ERR_ARG_OUTOFRANGE,
            "%s value %s (component %" PetscInt_FMT ") is out of range: expected %s", opt, num, i, desc);
  }
  if (set) *set = given;
  PetscFunctionReturn(0);
}
