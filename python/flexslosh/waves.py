"""Linear standing waves: the exact viscous mode and the fit of a decaying oscillation.

The standing-wave validation (tests/python/test_standing_wave.py, ``make validate``) compares the
decay of a sloshing mode with linear theory: :func:`exact_viscous_mode` gives the mode's frequency
and energy decay rate with the viscosity included (Lamb's relation at finite depth),
:func:`fit_decaying_wave` measures them from the mode's amplitude a(t) (the time series' column
mode_amplitude: the particles' velocity projected on the mode's) and :func:`fit_decaying_oscillation`
from the kinetic energy E_k(t). The amplitude is the wave's alone; the kinetic energy also holds the
particles' small-scale motion (the settling at the walls, noise), which in 3-D at h/dx = 10 is as large
as the wave's own energy at the start (docs/walls.md). A fit over the whole record is used
rather than the times of the energy's maxima, which other, slower motions beside the mode (the
start-up's own) shift: in the 3-D box at h/dx = 20 the maxima give a period 3.5 % long, the fit 1.4 %
(docs/walls.md).
"""
from __future__ import annotations

import numpy as np

__all__ = ["exact_viscous_mode", "fit_decaying_oscillation", "fit_decaying_wave"]


def exact_viscous_mode(k: float, h: float, nu: float, g: float = 1.0, floor: str = "free-slip") -> tuple[float, float]:
    """The root s = -lam/2 + i w of the linearized Navier-Stokes mode cos(kx) in liquid h deep under
    a stress-free surface, on a free-slip or a no-slip floor (free-slip side walls satisfy the mode
    exactly). The vertical velocity is V(y) cos(kx) e^(st) with
      V = a cosh(ky) + b sinh(ky) + c e^(-my) + d e^(m(y-h)),  m^2 = k^2 + s/nu
    (the potential part and the two boundary layers), the pressure -rho s (a sinh(ky) + b cosh(ky))/k
    cos(kx) e^(st), the horizontal velocity -V'(y)/k sin(kx) e^(st). The floor y = 0 has V = 0 and
    V'' = 0 (free-slip: no shear) or V' = 0 (no-slip: u = 0); the surface y = h has no shear,
    V'' + k^2 V = 0, and no normal stress, g V/s - p/rho + 2 nu V' = 0 (the kinematic condition
    s eta = V). The determinant of these four conditions in (a, b, c, d) vanishes at s: Newton from
    s = -2 nu k^2 + i sqrt(g k tanh(kh)). Free-slip it is Lamb's relation at finite depth; with
    nu -> 0 the decay tends to 4 nu k^2, plus on a no-slip floor the Stokes layer's dissipation
    rho/2 sqrt(nu w/2) U^2 per unit area (U the potential flow's speed at the floor).
    Returns (w, lam): E_k oscillates at 2w and decays at lam."""
    if floor not in ("free-slip", "no-slip"):
        raise ValueError(f"floor {floor!r}: expected 'free-slip' or 'no-slip'")

    def det(s):
        m = np.sqrt(k * k + s / nu)
        C, S, E = np.cosh(k * h), np.sinh(k * h), np.exp(-m * h)
        rows = [[1, 0, 1, E],
                [0, k, -m, m * E] if floor == "no-slip" else [k * k, 0, m * m, m * m * E],
                [2 * k * k * C, 2 * k * k * S, (m * m + k * k) * E, m * m + k * k],
                [g * C / s + s * S / k + 2 * nu * k * S, g * S / s + s * C / k + 2 * nu * k * C,
                 g * E / s - 2 * nu * m * E, g / s + 2 * nu * m]]
        return np.linalg.det(np.array(rows, dtype=complex))

    s = complex(-2 * nu * k * k, np.sqrt(g * k * np.tanh(k * h)))
    for _ in range(50):
        ds = 1e-7 * abs(s)
        step = det(s) / ((det(s + ds) - det(s - ds)) / (2 * ds))
        s -= step
        if abs(step) < 1e-14 * abs(s):
            break
    return float(s.imag), float(-2 * s.real)


def _fit_grid(t: np.ndarray, y: np.ndarray, omega0: float, rate_span: float, columns) -> tuple[float, float, np.ndarray]:
    """Least squares of y(t) on the model columns(w, rate) (an n x 3 matrix, linear in its coefficients):
    (w, rate) minimize the residual on a grid of 21 x 21 around (omega0, 0), +-0.1 omega0 and +-rate_span,
    refined five-fold six times (to about 1e-5 omega0); returns (w, rate, coefficients)."""
    def solve(w, rate):
        M = columns(w, rate)
        coef = np.linalg.lstsq(M, y, rcond=None)[0]
        return np.sum((M @ coef - y) ** 2), coef

    w, rate, dw, dr = omega0, 0.0, 0.1 * omega0, rate_span
    for _ in range(6):
        ws, rs = w + dw * np.linspace(-1, 1, 21), rate + dr * np.linspace(-1, 1, 21)
        r = np.array([[solve(a, b)[0] for b in rs] for a in ws])
        i, j = np.unravel_index(np.argmin(r), r.shape)
        w, rate, dw, dr = ws[i], rs[j], dw / 5, dr / 5
    return float(w), float(rate), solve(w, rate)[1]


def fit_decaying_oscillation(t: np.ndarray, e: np.ndarray, omega0: float) -> tuple[float, float, np.ndarray]:
    """Fits e(t) ~ exp(-lam t) (a + b cos 2wt + c sin 2wt); returns (w, lam, (a, b, c)).

    For given (w, lam) the model is linear in (a, b, c) (least squares); (w, lam) minimize the
    residual on a grid around (omega0, 0), refined five-fold six times (to about 1e-5 omega0)."""
    def columns(w, lam):
        x = np.exp(-lam * t)
        return np.stack([x, x * np.cos(2 * w * t), x * np.sin(2 * w * t)], axis=1)

    return _fit_grid(t, e, omega0, 0.2, columns)


def fit_decaying_wave(t: np.ndarray, a: np.ndarray, omega0: float) -> tuple[float, float, np.ndarray]:
    """Fits a(t) ~ exp(-mu t) (b cos wt + c sin wt) + d, a mode's amplitude; returns (w, 2 mu, (b, c, d)).

    2 mu is the decay rate of the mode's energy (the energy goes as the amplitude squared), the same
    quantity as the lam of :func:`fit_decaying_oscillation`. For given (w, mu) the model is linear in
    (b, c, d) (least squares); (w, mu) minimize the residual on a grid around (omega0, 0), refined
    five-fold six times (to about 1e-5 omega0)."""
    def columns(w, mu):
        x = np.exp(-mu * t)
        return np.stack([x * np.cos(w * t), x * np.sin(w * t), np.ones_like(t)], axis=1)

    w, mu, coef = _fit_grid(t, a, omega0, 0.1, columns)
    return w, 2 * mu, coef
