#!/usr/bin/env python3
"""Linear (von Neumann / matrix) stability analysis of the mpm1d time step.

The one-step update of mpm1d (USF, USL, MUSL; see STABILITY_THEORY.md) is linearised about
the rest state: particle positions are frozen at their initial places (sub-cell centres), so
the shape functions N_I(x_p) and gradients dN_I(x_p) are constants, and J = 1 (so
sigma_p V_p = sigma_p V0).  The step is then a linear map

    z_{n+1} = A z_n,     z = (v_1..v_Np, sigma_1..sigma_Np),

built here by applying a literal transcription of the step to the unit vectors.  The
spectral radius rho(A) decides stability; the critical time-step fraction k_crit is the end
of the interval (0, k_crit] of k = c dt / dx on which rho(A) <= 1 + tol.

Structure used (and checked numerically): the step depends on v only through the nodal
momenta N v and on sigma only through the nodal forces B sigma (B_Ip = dN_I(x_p), free and
non-empty nodes only), and its increments lie in range(N^T) x range(B^T).  Hence, with
K = ker N x ker B and R = K^perp, A = I on K and A maps R into R: A is block diagonal in
(K, R).  The eigenvalue 1 of K (zero-energy particle modes, present for ppc > 1) is
therefore semisimple (no Jordan block, no polynomial growth), and rho(A) = max(1, rho(A_R))
with A_R = Q_R^T A Q_R, a matrix of size <= 2 * (free nodes).

Units: any E, rho, L; the result depends only on k, ppc, ne (a diagonal similarity
sigma = rho c s makes A dimensionless).  E = rho = L = 1 by default.

Run `python3 linear_stability.py --help`.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path
import sys
from dataclasses import dataclass, field

import numpy as np

from .output_files import replacing, save_figure_file, with_output_errors

PROGRAM = "mpm1d-linear-stability"

SCHEMES = ("usf", "usl", "musl")

#: Default tolerance on the spectral radius: a mode is called unstable when |lambda| > 1 + TOL.
#: Round-off in the eigenvalues of the (<= 2 ne x 2 ne) reduced matrix is ~1e-14; a growth
#: of 1e-10 per step is a factor 1 + 1e-5 after 1e5 steps, i.e. invisible in any run.
TOL = 1.0e-10

#: Nodes lighter than this fraction of one particle's mass are skipped (as in mpm_grid).
MASS_TOLERANCE = 1.0e-12


# --------------------------------------------------------------------------------------------
# Model: frozen shape functions and the literal one-step update
# --------------------------------------------------------------------------------------------


@dataclass
class Model:
    """Linearised mpm1d discretisation of a bar with frozen particle positions.

    boundary = 'bar': nodes 0..ne, node 0 fixed, node ne free (what mpm1d does).
    boundary = 'periodic': nodes 0..ne-1, node ne identified with node 0, nothing fixed
    (used only by the tests, to compare with a Fourier analysis).
    shape = 'linear' (default), 'ugimp', 'cpgimp' (the same at J = 1), 'bspline2', 'bspline3'
    (bar only): the wider shapes as mpm1d builds them, with a ghost node left of the fixed node
    folded as its mirror (momentum and force rows N_1 - N_-1, mass N_1 + N_-1) and one more empty
    cell beyond the free end. `stretch` (wide shapes only) evaluates them at x (1 + stretch): a
    slightly stretched bar, whose end box or support just enters the margin cell and gives its
    node a nearly empty mass (what limits GIMP's USL step; see studies/shapes).
    """

    elements: int
    ppc: int
    length: float = 1.0
    density: float = 1.0
    youngs: float = 1.0
    boundary: str = "bar"
    shape: str = "linear"
    stretch: float = 0.0
    dx: float = field(init=False)
    mass: float = field(init=False)
    volume0: float = field(init=False)
    x: np.ndarray = field(init=False)
    N: np.ndarray = field(init=False)      # (nodes, Np)  N_I(x_p)
    dN: np.ndarray = field(init=False)     # (nodes, Np)  dN_I/dx(x_p)
    node_mass: np.ndarray = field(init=False)
    free: np.ndarray = field(init=False)   # nodes that are neither fixed nor empty

    def __post_init__(self) -> None:
        if self.elements < 1 or self.ppc < 1:
            raise ValueError("elements and ppc must be >= 1")
        if self.boundary not in ("bar", "periodic"):
            raise ValueError("boundary must be 'bar' or 'periodic'")
        ne, ppc = self.elements, self.ppc
        self.dx = self.length / ne
        sub = self.dx / ppc
        self.volume0 = sub
        self.mass = self.density * sub
        npart = ne * ppc
        nodes = ne + 1 if self.boundary == "bar" else ne
        self.x = np.empty(npart)
        self.N = np.zeros((nodes, npart))
        self.dN = np.zeros((nodes, npart))
        for e in range(ne):             # element e (0-based) spans nodes e and e+1
            for j in range(ppc):
                p = e * ppc + j
                xi = (j + 0.5) / ppc
                self.x[p] = e * self.dx + xi * self.dx
                left, right = e, (e + 1) % nodes
                self.N[left, p] += 1.0 - xi
                self.N[right, p] += xi
                self.dN[left, p] += -1.0 / self.dx
                self.dN[right, p] += 1.0 / self.dx
        self.node_mass = self.N @ np.full(npart, self.mass)
        if self.shape != "linear":
            if self.boundary != "bar":
                raise ValueError("shapes other than linear: boundary 'bar' only")
            self._wide_shape()
        self.free = self.node_mass > MASS_TOLERANCE * self.mass
        if self.boundary == "bar":
            self.free[0] = False

    def _wide_shape(self) -> None:
        """N, dN and nodal masses of a wide shape on nodes 0..ne+1 with node -1 mirrored into 1."""
        ne = self.elements
        nodes = np.arange(-1, ne + 2)                       # ghost, body nodes, one margin node
        u = (self.x[None, :] * (1.0 + self.stretch) - nodes[:, None] * self.dx) / self.dx
        w, g = shape_values(self.shape, u, 1.0 / (2 * self.ppc))
        g = g / self.dx
        ghost, partner = 0, 2                                 # rows of nodes -1 and +1
        n_odd, g_odd = w[1:].copy(), g[1:].copy()
        n_odd[partner - 1] -= w[ghost]
        g_odd[partner - 1] -= g[ghost]
        n_even = w[1:].copy()
        n_even[partner - 1] += w[ghost]
        self.N, self.dN = n_odd, g_odd
        self.node_mass = n_even @ np.full(self.particles, self.mass)

    @property
    def particles(self) -> int:
        return self.elements * self.ppc

    @property
    def wave_speed(self) -> float:
        return math.sqrt(self.youngs / self.density)

    def dt(self, k: float) -> float:
        return k * self.dx / self.wave_speed

    # ---- grid operations, column-vectorised (v, sigma may be (Np,) or (Np, ncols)) ----

    def _mask(self, g: np.ndarray) -> np.ndarray:
        g = g.copy()
        g[~self.free] = 0.0
        return g

    def p2g_momentum(self, v):
        return self._mask(self.N @ (self.mass * v))

    def internal_force(self, sigma):
        # f_I = -sum_p dN_I(x_p) sigma_p V_p, V_p = J V0 with J = 1 (linearisation)
        return self._mask(-self.dN @ (sigma * self.volume0))

    def _per_mass(self, g):
        out = np.zeros_like(g)
        m = self.node_mass if g.ndim == 1 else self.node_mass[:, None]
        out[self.free] = g[self.free] / m[self.free]
        return out

    def step(self, scheme: str, k: float, v, sigma):
        """One linearised mpm1d step; returns (v_new, sigma_new)."""
        dt = self.dt(k)
        E = self.youngs
        N, dN = self.N, self.dN
        if scheme == "usl":
            p = self.p2g_momentum(v)
            f = self.internal_force(sigma)
            p = p + dt * f
            a = self._per_mass(f)
            vI = self._per_mass(p)
            v_new = v + dt * (N.T @ a)
            de = dt * (dN.T @ vI)
            return v_new, sigma + E * de
        if scheme == "usf":
            p = self.p2g_momentum(v)
            vI = self._per_mass(p)
            de = dt * (dN.T @ vI)
            sigma_new = sigma + E * de
            f = self.internal_force(sigma_new)
            p = p + dt * f
            a = self._per_mass(f)
            v_new = v + dt * (N.T @ a)
            return v_new, sigma_new
        if scheme == "musl":
            p = self.p2g_momentum(v)
            f = self.internal_force(sigma)
            p = p + dt * f
            a = self._per_mass(f)
            v_new = v + dt * (N.T @ a)
            p2 = self.p2g_momentum(v_new)       # remap with start-of-step N, fixed node held
            vI2 = self._per_mass(p2)
            de = dt * (dN.T @ vI2)
            return v_new, sigma + E * de
        raise ValueError(f"unknown scheme {scheme!r}; known: {', '.join(SCHEMES)}")

    # ---- the linear map ----

    def amplification_matrix(self, scheme: str, k: float) -> np.ndarray:
        """A with z_{n+1} = A z_n, z = (v, sigma), built from the step applied to unit vectors."""
        n = self.particles
        eye = np.eye(2 * n)
        v_new, s_new = self.step(scheme, k, eye[:n, :], eye[n:, :])
        return np.vstack([v_new, s_new])

    def subspaces(self):
        """Orthonormal bases (Q_R, Q_K) of R = range(N_f^T) x range(B_f^T) and K = R^perp."""
        n = self.particles
        rows_v = self.N[self.free]
        rows_s = self.dN[self.free]
        qv_r, qv_k = _range_and_null(rows_v.T)
        qs_r, qs_k = _range_and_null(rows_s.T)
        QR = np.zeros((2 * n, qv_r.shape[1] + qs_r.shape[1]))
        QR[:n, : qv_r.shape[1]] = qv_r
        QR[n:, qv_r.shape[1]:] = qs_r
        QK = np.zeros((2 * n, qv_k.shape[1] + qs_k.shape[1]))
        QK[:n, : qv_k.shape[1]] = qv_k
        QK[n:, qv_k.shape[1]:] = qs_k
        return QR, QK

    def reduced_matrix(self, scheme: str, k: float, QR=None) -> np.ndarray:
        if QR is None:
            QR, _ = self.subspaces()
        A = self.amplification_matrix(scheme, k)
        return QR.T @ A @ QR


def shape_values(shape: str, u: np.ndarray, half_length: float = 0.25):
    """Weights N(u) and derivatives dN/du of a shape at u = (x_p - x_I)/dx (GIMP: box half-length
    `half_length` cells). Written from the formulas (Bardenhagen & Kober 2004; Steffen, Kirby &
    Berzins 2008) independently of mpm1d's Fortran, so that the two check each other."""
    r = np.abs(u)
    if shape == "linear":
        return np.maximum(0.0, 1.0 - r), np.where(r < 1.0, -np.sign(u), 0.0)
    if shape in ("ugimp", "cpgimp"):
        def antiderivative(t):
            c = np.clip(t, -1.0, 1.0)
            return 0.5 + c - 0.5 * c * np.abs(c)
        l = half_length
        w = (antiderivative(u + l) - antiderivative(u - l)) / (2 * l)
        d = (np.maximum(0.0, 1.0 - np.abs(u + l)) - np.maximum(0.0, 1.0 - np.abs(u - l))) / (2 * l)
        return w, d
    if shape == "bspline2":
        w = np.where(r < 0.5, 0.75 - r * r, np.where(r < 1.5, 0.5 * (1.5 - r) ** 2, 0.0))
        d = np.where(r < 0.5, -2.0 * u, np.where(r < 1.5, -np.sign(u) * (1.5 - r), 0.0))
        return w, d
    if shape == "bspline3":
        w = np.where(r < 1.0, 2.0 / 3.0 - r * r + 0.5 * r ** 3, np.where(r < 2.0, (2.0 - r) ** 3 / 6.0, 0.0))
        d = np.where(r < 1.0, -2.0 * u + 1.5 * u * r, np.where(r < 2.0, -0.5 * np.sign(u) * (2.0 - r) ** 2, 0.0))
        return w, d
    raise ValueError(f"unknown shape {shape!r}")


def _range_and_null(M: np.ndarray):
    """Orthonormal bases of range(M) and of its orthogonal complement (columns)."""
    u, s, _ = np.linalg.svd(M, full_matrices=True)
    rank = int(np.sum(s > s.max() * max(M.shape) * np.finfo(float).eps)) if s.size else 0
    return u[:, :rank], u[:, rank:]


# --------------------------------------------------------------------------------------------
# Spectral radius and critical time-step fraction
# --------------------------------------------------------------------------------------------


class Analyser:
    """Caches the model and subspaces of one (ppc, ne) for repeated evaluation over k."""

    def __init__(self, elements: int, ppc: int, boundary: str = "bar", **material):
        self.model = Model(elements, ppc, boundary=boundary, **material)
        self.QR, self.QK = self.model.subspaces()
        # A depends on k as A = I + k A1 + k^2 A2 (dt enters at most twice per step), so
        # three evaluations give it for every k exactly (up to round-off); the dimensionless
        # form removes E, rho, L.
        self._coeffs = {}

    def _poly(self, scheme):
        if scheme not in self._coeffs:
            m = self.model
            A0 = m.reduced_matrix(scheme, 0.0, self.QR)
            A1 = m.reduced_matrix(scheme, 1.0, self.QR)
            Am = m.reduced_matrix(scheme, -1.0, self.QR)
            c1 = 0.5 * (A1 - Am)
            c2 = 0.5 * (A1 + Am) - A0
            self._coeffs[scheme] = (A0, c1, c2)
        return self._coeffs[scheme]

    def reduced(self, scheme: str, k: float) -> np.ndarray:
        A0, c1, c2 = self._poly(scheme)
        return A0 + k * c1 + k * k * c2

    def spectral_radius(self, scheme: str, k: float) -> float:
        """rho(A) = max(1 if K is non-trivial, rho(A_R))."""
        ar = self.reduced(scheme, k)
        r = float(np.max(np.abs(np.linalg.eigvals(ar)))) if ar.size else 0.0
        if self.QK.shape[1] > 0:
            r = max(r, 1.0)
        return r

    def critical_fraction(self, scheme: str, k_max: float = 3.0, dk: float = 2.0e-3,
                          tol: float = TOL, xtol: float = 1.0e-12):
        """First loss of stability in (0, k_max]: returns (k_crit, restabilises).

        k_crit is the end of the interval (0, k_crit] on which rho(A) <= 1 + tol, located by a
        scan with step dk and bisection to xtol; k_crit = k_max if never unstable, 0 if already
        unstable at the first scan point.  `restabilises` is True when the scan finds a stable
        k again beyond k_crit (an island of stability; not expected here).
        """
        ks = np.arange(dk, k_max + 0.5 * dk, dk)
        stable = np.array([self.spectral_radius(scheme, k) <= 1.0 + tol for k in ks])
        if stable.all():
            return k_max, False
        i = int(np.argmin(stable))        # first unstable scan point
        if i == 0:
            lo, hi = 0.0, ks[0]
        else:
            lo, hi = ks[i - 1], ks[i]
        while hi - lo > xtol:
            mid = 0.5 * (lo + hi)
            if self.spectral_radius(scheme, mid) <= 1.0 + tol:
                lo = mid
            else:
                hi = mid
        return lo, bool(stable[i:].any())

    # ---- structural checks ----

    def block_structure_error(self, scheme: str, k: float) -> float:
        """max(|A Q_K - Q_K|, |Q_K^T A Q_R|): zero when A = I on K and R is invariant."""
        if self.QK.shape[1] == 0:
            return 0.0
        A = self.model.amplification_matrix(scheme, k)
        e1 = np.max(np.abs(A @ self.QK - self.QK))
        e2 = np.max(np.abs(self.QK.T @ A @ self.QR))
        return float(max(e1, e2))

    def unit_modulus_report(self, scheme: str, k: float, band: float = 1.0e-6):
        """Eigenvalues of A_R with ||lambda| - 1| < band, and whether any is defective.

        Returns (count_on_circle_in_R, dim_K, defective).  A cluster of eigenvalues near lambda
        is defective when its size (algebraic multiplicity) exceeds dim null(A_R - lambda I)
        (geometric multiplicity, by SVD with a relative threshold of 1e-7).
        """
        ar = self.reduced(scheme, k)
        lam = np.linalg.eigvals(ar)
        on = lam[np.abs(np.abs(lam) - 1.0) < band]
        defective = False
        used = np.zeros(on.size, bool)
        scale = max(1.0, np.linalg.norm(ar, 2))
        for i in range(on.size):
            if used[i]:
                continue
            cluster = np.abs(on - on[i]) < 1.0e-5
            used |= cluster
            alg = int(cluster.sum())
            if alg == 1:
                continue
            s = np.linalg.svd(ar - on[i] * np.eye(ar.shape[0]), compute_uv=False)
            geo = int(np.sum(s < 1.0e-7 * scale))
            if geo < alg:
                defective = True
        return int(on.size), int(self.QK.shape[1]), defective


def rho_map(scheme: str, ks, ppcs, elements: int = 10, **material) -> np.ndarray:
    """rho(A) on the grid (ppc, k): array of shape (len(ppcs), len(ks))."""
    out = np.empty((len(ppcs), len(ks)))
    for i, ppc in enumerate(ppcs):
        an = Analyser(elements, ppc, **material)
        for j, k in enumerate(ks):
            out[i, j] = an.spectral_radius(scheme, float(k))
    return out


def energy_ratios(scheme: str, k: float, ppc: int, elements: int, steps: int, mode: int = 1,
                  **material):
    """Linearised run of the bar from mpm1d's initial state: (max, final) energy ratio.

    Iterates the linearised step (`Model.step`) for `steps` steps from v_p = sin(beta_n X_p),
    sigma = 0, and measures the energy as mpm1d does (kinetic sum m v^2/2 plus strain
    sum sigma^2 V0/(2E)) relative to its initial value.  This predicts what the energy_growth
    guard sees in a linearly stable run: the particle energy is not the invariant of the
    discrete map, so it oscillates, and for a few coarse cases close to k_crit its maximum
    exceeds the guard's limit although rho(A) <= 1.  Amplitude-independent (linear).
    """
    m = Model(elements, ppc, **material)
    beta = (2 * mode - 1) * math.pi / (2 * m.length)
    n = m.particles
    A = m.amplification_matrix(scheme, k)      # iterate z = A z: the same map, much faster
    z = np.concatenate([np.sin(beta * m.x), np.zeros(n)])
    weight = np.concatenate([np.full(n, 0.5 * m.mass), np.full(n, 0.5 * m.volume0 / m.youngs)])
    e0 = float(weight @ (z * z))
    emax, e = 1.0, 1.0
    for _ in range(int(steps)):
        z = A @ z
        e = float(weight @ (z * z)) / e0
        emax = max(emax, e)
        if e > 1.0e100:                 # clearly unstable: stop before overflow
            return math.inf, math.inf
    return emax, e


def spectral_radius(scheme: str, k: float, ppc: int, elements: int, **material) -> float:
    """Convenience: rho(A) of one case, from the full (unreduced) matrix."""
    A = Model(elements, ppc, **material).amplification_matrix(scheme, k)
    return float(np.max(np.abs(np.linalg.eigvals(A))))


# --------------------------------------------------------------------------------------------
# Command line
# --------------------------------------------------------------------------------------------


def _int_list(text: str):
    out = []
    for part in text.split(","):
        part = part.strip()
        if "-" in part:
            a, b = part.split("-")
            out.extend(range(int(a), int(b) + 1))
        elif part:
            out.append(int(part))
    if not out or min(out) < 1:
        raise argparse.ArgumentTypeError(f"expected positive integers like '1-8' or '10,20', got {text!r}")
    return out


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="mpm1d-linear-stability",
        description="Predicted critical time-step fraction k = c dt/dx of mpm1d (USF/USL/MUSL) "
                    "from the spectral radius of the linearised one-step map.")
    p.add_argument("--schemes", default="usf,usl,musl",
                   help="comma-separated schemes (default: usf,usl,musl)")
    p.add_argument("--ppc", type=_int_list, default=list(range(1, 9)),
                   help="particles per element, e.g. '1-8' or '1,2,4' (default: 1-8)")
    p.add_argument("--elements", type=_int_list, default=[10, 20],
                   help="element counts, e.g. '10,20' (default: 10,20)")
    p.add_argument("--out", default="out",
                   help="output folder (default: out in the current folder)")
    p.add_argument("--tol", type=float, default=TOL,
                   help=f"unstable when rho(A) > 1 + tol (default: {TOL:g})")
    p.add_argument("--k-max", type=float, default=3.0, help="upper end of the k scan (default: 3)")
    p.add_argument("--dk", type=float, default=2.0e-3, help="scan step in k before bisection (default: 0.002)")
    p.add_argument("--map", action="store_true",
                   help="also write rho(A) maps over (k, ppc) as CSV and PNG (rho_map_<scheme>.*)")
    p.add_argument("--map-elements", type=int, default=10, help="elements for the maps (default: 10)")
    p.add_argument("--shapes", default="",
                   help="comma-separated shapes (linear, ugimp, cpgimp, bspline2, bspline3): write "
                        "predicted_shapes.csv, k_crit per scheme x shape x ppc x elements at rest and "
                        "stretched by --stretch, instead of the linear tables")
    p.add_argument("--stretch", type=float, default=1.0e-6,
                   help="uniform stretch of the second --shapes analysis (default: 1e-6)")
    p.add_argument("--scaling-check", action="store_true",
                   help="also show that rho(A) does not depend on E, rho, L")
    return p


def main(argv=None) -> int:
    """Command-line entry point; returns the exit status (3: a file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


def _main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    schemes = [s.strip().lower() for s in args.schemes.split(",") if s.strip()]
    bad = [s for s in schemes if s not in SCHEMES]
    if bad:
        print(f"error: unknown scheme(s) {bad}; known: {', '.join(SCHEMES)}", file=sys.stderr)
        return 2
    if not (args.tol >= 0 and args.k_max > 0 and 0 < args.dk < args.k_max):
        print("error: need tol >= 0, k-max > 0, 0 < dk < k-max", file=sys.stderr)
        return 2
    Path(args.out).mkdir(parents=True, exist_ok=True)
    if args.shapes:
        return shapes_command(args, schemes)

    rows, details = [], []
    for ne in args.elements:
        for ppc in args.ppc:
            an = Analyser(ne, ppc)
            for scheme in schemes:
                kc, island = an.critical_fraction(scheme, k_max=args.k_max, dk=args.dk, tol=args.tol)
                kprobe = 0.5 * kc
                on, dimk, defective = an.unit_modulus_report(scheme, kprobe)
                block_err = an.block_structure_error(scheme, kprobe)
                rows.append((scheme, ppc, ne, kc))
                details.append((scheme, ppc, ne, kc, island, dimk, on, defective, block_err))

    path = Path(args.out) / "predicted_critical.csv"
    with replacing(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scheme", "particles_per_element", "elements", "k_crit"])
        for s, ppc, ne, kc in rows:
            w.writerow([s, ppc, ne, f"{kc:.10f}"])
    dpath = Path(args.out) / "predicted_critical_details.csv"
    with replacing(dpath, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scheme", "particles_per_element", "elements", "k_crit", "restabilises",
                    "zero_energy_modes_lambda1", "unit_modulus_eigs_in_R_at_half_kcrit",
                    "defective_unit_modulus", "block_structure_error"])
        for r in details:
            w.writerow([r[0], r[1], r[2], f"{r[3]:.10f}", int(r[4]), r[5], r[6], int(r[7]), f"{r[8]:.1e}"])

    # table: rows ppc, columns scheme x elements
    print(f"Predicted critical dt fraction k_crit = c dt/dx  (rho(A) <= 1 + {args.tol:g})")
    header = "ppc " + "".join(f"{s.upper() + ' ne=' + str(ne):>15}" for s in schemes for ne in args.elements)
    print(header)
    lookup = {(s, p, n): kc for s, p, n, kc in rows}
    for ppc in args.ppc:
        print(f"{ppc:>3} " + "".join(f"{lookup[(s, ppc, ne)]:>15.6f}" for s in schemes for ne in args.elements))
    notes = [d for d in details if d[4] or d[7] or d[8] > 1e-10]
    print(f"zero-energy (lambda = 1, semisimple) modes: "
          + ", ".join(f"ppc={p}: {d}" for p, d in sorted({(r[1], r[5]) for r in details if r[2] == args.elements[0]})))
    if notes:
        for d in notes:
            print(f"note: {d[0]} ppc={d[1]} ne={d[2]}: restabilises={d[4]} defective={d[7]} "
                  f"block_err={d[8]:.1e}")
    else:
        print("no defective unit-modulus eigenvalues, no islands of stability above k_crit, "
              "block structure exact")
    print(f"wrote {path}")
    print(f"wrote {dpath}")

    if args.scaling_check:
        print("scaling check: rho(A) at k = 0.5 for (E, rho, L) = (1,1,1), (2e11, 7850, 3), (1e6, 1000, 0.01)")
        for s in schemes:
            vals = [spectral_radius(s, 0.5, 2, 10, youngs=E, density=r, length=L)
                    for E, r, L in ((1, 1, 1), (2e11, 7850, 3), (1e6, 1000, 0.01))]
            print(f"  {s}: " + "  ".join(f"{v:.15f}" for v in vals))

    if args.map:
        ks = np.linspace(0.01, args.k_max, 300)
        ppcs = list(args.ppc)
        for s in schemes:
            rm = rho_map(s, ks, ppcs, args.map_elements)
            mpath = Path(args.out) / f"rho_map_{s}.csv"
            with replacing(mpath, "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["particles_per_element", "k", "rho"])
                for i, ppc in enumerate(ppcs):
                    for j, k in enumerate(ks):
                        w.writerow([ppc, f"{k:.6f}", f"{rm[i, j]:.15e}"])
            _plot_map(s, ks, ppcs, rm, args.map_elements, Path(args.out) / f"rho_map_{s}.png")
            print(f"wrote {mpath} (+ .png)")
    return 0


def shapes_command(args, schemes) -> int:
    """k_crit per scheme x shape x ppc x elements, at rest and stretched: predicted_shapes.csv."""
    shapes = [s.strip() for s in args.shapes.split(",") if s.strip()]
    path = Path(args.out) / "predicted_shapes.csv"
    print(f"Predicted critical dt fraction per shape (at rest / stretched by {args.stretch:g})")
    with replacing(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scheme", "shape", "particles_per_element", "elements", "k_crit_rest", "k_crit_stretched"])
        for ne in args.elements:
            for shape in shapes:
                for ppc in args.ppc:
                    rest = Analyser(ne, ppc, shape=shape)
                    stretched = Analyser(ne, ppc, shape=shape, stretch=args.stretch) if shape != "linear" else rest
                    for scheme in schemes:
                        k0, _ = rest.critical_fraction(scheme, k_max=args.k_max, dk=args.dk, tol=args.tol)
                        k1, _ = stretched.critical_fraction(scheme, k_max=args.k_max, dk=args.dk, tol=args.tol)
                        w.writerow([scheme, shape, ppc, ne, f"{k0:.6f}", f"{k1:.6f}"])
                        print(f"{scheme:5s} {shape:9s} ppc={ppc} ne={ne}: {k0:.4f} / {k1:.4f}")
    print(f"wrote {path}")
    return 0


def _plot_map(scheme, ks, ppcs, rm, ne, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 3.5))
    lg = np.log10(np.maximum(rm - 1.0, 1e-16))
    im = ax.pcolormesh(ks, ppcs, lg, shading="nearest", cmap="magma", vmin=-12, vmax=1)
    ax.contour(ks, ppcs, rm, levels=[1.0 + TOL], colors="cyan", linewidths=1)
    ax.set_xlabel("k = c dt / dx")
    ax.set_ylabel("particles per element")
    ax.set_title(f"{scheme.upper()}: log10(rho(A) - 1), ne = {ne}")
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    save_figure_file(fig, path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
