/*
   A tank turned about any axis: the rotation of a motion (FSTankMotion) built from elementary turns,
   each about an axis fixed in the tank as the turns before it left it (intrinsic turns). With
   Q_k = Q_{k-1} R_k, R_k the turn by phi_k about the unit axis n_k, the angular velocity in the tank's
   axes and its rate follow from Q^T Q' = [w]x:

     w_k  = R_k^T w_{k-1} + phi_k' n_k
     dw_k = R_k^T dw_{k-1} - phi_k' n_k x (R_k^T w_{k-1}) + phi_k'' n_k

   (R_k' = phi_k' [n_k]x R_k and R_k n_k = n_k). The prescribed structure composes its pitch, yaw, roll
   and the rotation about a given axis so (src/structure/impls/prescribed.c); the coupling's tank frame
   uses Q, w, dw (src/coupling/coupling.c).
*/
#include <flexslosh.h>

/*@
   FSTankMotionRotate - turns a tank's motion further about an axis fixed in the tank (intrinsic): Q <- Q R,
   with the angular velocity and acceleration in the tank's axes updated (above). A motion not yet rotated
   (rotated 0) starts from Q = I, w = dw = 0 (its angle, rate and angacc are left as they are, for the
   output).

   Input Parameters:
+  m     - the motion
.  axis  - the axis in the tank's axes after the turns before (normalized here; not zero)
-  angle - the angle (rad), its rate and its acceleration

   Not collective
@*/
PetscErrorCode FSTankMotionRotate(FSTankMotion *m, const PetscReal axis[3], const PetscReal angle[3])
{
  const PetscReal len = PetscSqrtReal(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  PetscReal       n[3], R[9], Q[9], w[3], dw[3], c, s, C;

  PetscFunctionBegin;
  PetscCheck(len > 0 && !PetscIsInfOrNanReal(len), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "FSTankMotionRotate: the axis (%g, %g, %g) has no direction", (double)axis[0], (double)axis[1],
             (double)axis[2]);
  if (m->rotated == 0) {
    PetscCall(PetscArrayzero(m->Q, 9));
    m->Q[0] = m->Q[4] = m->Q[8] = 1;
    PetscCall(PetscArrayzero(m->w, 3));
    PetscCall(PetscArrayzero(m->dw, 3));
    m->rotated = 1;
  }
  for (PetscInt d = 0; d < 3; d++) n[d] = axis[d] / len;
  c = PetscCosReal(angle[0]);
  s = PetscSinReal(angle[0]);
  C = 1 - c;
  /* Rodrigues: R = c I + s [n]x + (1 - c) n n^T */
  R[0] = c + C * n[0] * n[0];
  R[1] = C * n[0] * n[1] - s * n[2];
  R[2] = C * n[0] * n[2] + s * n[1];
  R[3] = C * n[1] * n[0] + s * n[2];
  R[4] = c + C * n[1] * n[1];
  R[5] = C * n[1] * n[2] - s * n[0];
  R[6] = C * n[2] * n[0] - s * n[1];
  R[7] = C * n[2] * n[1] + s * n[0];
  R[8] = c + C * n[2] * n[2];
  for (PetscInt i = 0; i < 3; i++) {
    for (PetscInt j = 0; j < 3; j++)
      Q[3 * i + j] = m->Q[3 * i] * R[j] + m->Q[3 * i + 1] * R[3 + j] + m->Q[3 * i + 2] * R[6 + j];
    w[i]  = R[i] * m->w[0] + R[3 + i] * m->w[1] + R[6 + i] * m->w[2]; /* R^T w */
    dw[i] = R[i] * m->dw[0] + R[3 + i] * m->dw[1] + R[6 + i] * m->dw[2];
  }
  dw[0] += angle[2] * n[0] - angle[1] * (n[1] * w[2] - n[2] * w[1]);
  dw[1] += angle[2] * n[1] - angle[1] * (n[2] * w[0] - n[0] * w[2]);
  dw[2] += angle[2] * n[2] - angle[1] * (n[0] * w[1] - n[1] * w[0]);
  for (PetscInt d = 0; d < 3; d++) {
    m->w[d]  = w[d] + angle[1] * n[d];
    m->dw[d] = dw[d];
  }
  PetscCall(PetscArraycpy(m->Q, Q, 9));
  PetscFunctionReturn(0);
}
