#!/usr/bin/env python3
"""Checks of linear_stability.py against independent (hand-derived) expectations.

Run as a plain script (`.venv/bin/python studies/stability/test_linear_stability.py`; last line
`N passed, M failed`, exit status 1 on any failure) or with pytest.

Hand results used (E = rho = L = 1 so c = 1, k = dt/dx, and sigma is already the
non-dimensional stress sigma/(rho c)); derivations in STABILITY_THEORY.md:

* One element, one particle at its centre (N = 1/2, node 0 fixed, node 1 of mass m/2):
    USL  A = [[1, -k], [k, 1 - 2k^2]]   -> k_crit = 2/sqrt(3)
    USF  A = [[1 - k^2, -k], [k, 1]]    -> k_crit = 2
    MUSL A = [[1, -k], [k, 1 - k^2]]    -> k_crit = 2
* ppc = 1 (particles at element centres), Fourier mode v_e ~ e^{i theta e}, a = k sin(theta),
  b = 4 k^2 sin^2(theta/2):
    USL  G = [[1, i a], [i a, 1 - b]]    USF G = [[1 - a^2, i a], [i a, 1]]
    MUSL G = [[1, i a], [i a, 1 - a^2]]
  The fixed-free bar has exactly the modes theta_j = (2j - 1) pi / (2 ne), j = 1..ne (the
  bar extends by reflection to a periodic grid of 4 ne elements), so
    USL:      k_crit = 1 / (s sqrt(1 + s^2)),  s = cos(pi/(4 ne))  -> 1/sqrt(2) as ne -> inf
    USF/MUSL: k_crit = 2 / max_j sin(theta_j)                      -> 2
"""

from __future__ import annotations

import io
import math
import os
import sys
import tempfile
import contextlib

import numpy as np

from mpm1d_post import linear_stability as ls  # noqa: E402

SCHEMES = ls.SCHEMES


# ---------------------------------------------------------------------------------------------
# independent expectations
# ---------------------------------------------------------------------------------------------

def hand_one_element(scheme, k):
    if scheme == "usl":
        return np.array([[1.0, -k], [k, 1.0 - 2.0 * k * k]])
    if scheme == "usf":
        return np.array([[1.0 - k * k, -k], [k, 1.0]])
    return np.array([[1.0, -k], [k, 1.0 - k * k]])


def symbol(scheme, k, theta):
    a = k * math.sin(theta)
    b = 4.0 * k * k * math.sin(theta / 2) ** 2
    if scheme == "usl":
        return np.array([[1, 1j * a], [1j * a, 1 - b]])
    if scheme == "usf":
        return np.array([[1 - a * a, 1j * a], [1j * a, 1]])
    return np.array([[1, 1j * a], [1j * a, 1 - a * a]])


def analytic_kcrit_bar_ppc1(scheme, ne):
    if scheme == "usl":
        s = math.cos(math.pi / (4 * ne))
        return 1.0 / (s * math.sqrt(1.0 + s * s))
    th = [(2 * j - 1) * math.pi / (2 * ne) for j in range(1, ne + 1)]
    return 2.0 / max(math.sin(t) for t in th)


def match_spectra(a, b):
    """Largest distance after greedy nearest matching of two eigenvalue lists."""
    a, b = list(a), list(b)
    assert len(a) == len(b), (len(a), len(b))
    worst = 0.0
    for x in a:
        d = [abs(x - y) for y in b]
        i = int(np.argmin(d))
        worst = max(worst, d[i])
        b.pop(i)
    return worst


def eig(A):
    return np.linalg.eigvals(A)


# ---------------------------------------------------------------------------------------------
# tests
# ---------------------------------------------------------------------------------------------

def test_one_element_matrix_matches_hand_derivation():
    for s in SCHEMES:
        for k in (0.1, 0.7, 1.3, 2.5):
            A = ls.Model(1, 1).amplification_matrix(s, k)
            assert np.max(np.abs(A - hand_one_element(s, k))) < 1e-13, (s, k, A)


def test_one_element_kcrit_matches_hand_derivation():
    want = {"usl": 2.0 / math.sqrt(3.0), "usf": 2.0, "musl": 2.0}
    an = ls.Analyser(1, 1)
    for s in SCHEMES:
        kc, island = an.critical_fraction(s)
        assert abs(kc - want[s]) < 1e-9, (s, kc, want[s])
        assert not island


def test_bar_ppc1_spectrum_is_union_of_fourier_symbols():
    for ne in (3, 10):
        th = [(2 * j - 1) * math.pi / (2 * ne) for j in range(1, ne + 1)]
        for s in SCHEMES:
            for k in (0.3, 0.69, 1.5):
                got = eig(ls.Model(ne, 1).amplification_matrix(s, k))
                want = np.concatenate([eig(symbol(s, k, t)) for t in th])
                assert match_spectra(got, want) < 1e-9, (ne, s, k)


def test_periodic_ppc1_spectrum_is_union_of_fourier_symbols():
    ne = 8
    th = [2 * math.pi * j / ne for j in range(ne)]
    for s in SCHEMES:
        for k in (0.4, 0.9):
            got = eig(ls.Model(ne, 1, boundary="periodic").amplification_matrix(s, k))
            want = np.concatenate([eig(symbol(s, k, t)) for t in th])
            assert match_spectra(got, want) < 1e-9, (s, k)


def test_periodic_ppc1_kcrit_fourier_limits():
    # ne = 8 contains theta = pi (USL limit 1/sqrt 2) and theta = pi/2 (USF/MUSL limit 2)
    an = ls.Analyser(8, 1, boundary="periodic")
    want = {"usl": 1.0 / math.sqrt(2.0), "usf": 2.0, "musl": 2.0}
    for s in SCHEMES:
        kc, _ = an.critical_fraction(s)
        assert abs(kc - want[s]) < 1e-8, (s, kc)


def test_bar_ppc1_kcrit_matches_analytic_formula():
    for ne in (2, 5, 10, 20, 40):
        an = ls.Analyser(ne, 1)
        for s in SCHEMES:
            kc, _ = an.critical_fraction(s)
            want = analytic_kcrit_bar_ppc1(s, ne)
            assert abs(kc - want) < 1e-8, (ne, s, kc, want)


def test_usl_ppc1_tends_to_cfl_limit():
    prev = None
    for ne in (10, 20, 40, 80):
        kc, _ = ls.Analyser(ne, 1).critical_fraction("usl")
        assert kc > 1.0 / math.sqrt(2.0)
        if prev is not None:
            assert kc < prev
        prev = kc
    assert abs(prev - 1.0 / math.sqrt(2.0)) < 2e-4, prev


def test_scale_invariance():
    materials = [dict(), dict(youngs=2.0e11, density=7850.0, length=3.0),
                 dict(youngs=1.0e6, density=1000.0, length=0.01)]
    for s in SCHEMES:
        for k in (0.3, 0.77, 1.7, 2.2):
            r = [ls.spectral_radius(s, k, 3, 6, **m) for m in materials]
            assert max(r) - min(r) < 1e-11 * max(r), (s, k, r)
        kc = [ls.Analyser(6, 3, **m).critical_fraction(s)[0] for m in materials]
        assert max(kc) - min(kc) < 1e-9, (s, kc)


def test_small_k_is_stable():
    for ppc in range(1, 9):
        an = ls.Analyser(10, ppc)
        for s in SCHEMES:
            for k in (1e-4, 1e-2, 0.1, 0.5):
                assert an.spectral_radius(s, k) <= 1.0 + 1e-12, (s, ppc, k)


def test_reduced_equals_full_spectral_radius():
    for ppc in (1, 2, 5):
        an = ls.Analyser(7, ppc)
        for s in SCHEMES:
            for k in (0.2, 0.75, 1.0, 1.8, 2.6):
                full = ls.spectral_radius(s, k, ppc, 7)
                red = an.spectral_radius(s, k)
                assert abs(full - red) < 1e-8 * max(1.0, full), (ppc, s, k, full, red)


def test_zero_energy_modes_are_identity_block_not_jordan():
    for ppc in (1, 2, 4, 8):
        ne = 10
        an = ls.Analyser(ne, ppc)
        assert an.QK.shape[1] == 2 * (ne * ppc - ne), (ppc, an.QK.shape)
        for s in SCHEMES:
            k = 0.5
            assert an.block_structure_error(s, k) < 1e-12, (ppc, s)
            # full matrix: geometric multiplicity of lambda = 1 equals dim K (R has no lambda = 1)
            A = an.model.amplification_matrix(s, k)
            sv = np.linalg.svd(A - np.eye(A.shape[0]), compute_uv=False)
            geo = int(np.sum(sv < 1e-9))
            assert geo == an.QK.shape[1], (ppc, s, geo)
            # A^n z stays exactly bounded on K (polynomial growth would show up here)
            if an.QK.shape[1]:
                An = np.linalg.matrix_power(A, 200)
                assert np.max(np.abs(An @ an.QK - an.QK)) < 1e-9
            _, _, defective = an.unit_modulus_report(s, k)
            assert not defective, (ppc, s)


def test_usf_and_musl_are_similar():
    # A_USF = K S and A_MUSL = S K (stress update S, velocity kick K): same spectrum
    for ppc in (1, 3):
        m = ls.Model(6, ppc)
        for k in (0.5, 1.2, 1.9):
            a = eig(m.amplification_matrix("usf", k))
            b = eig(m.amplification_matrix("musl", k))
            assert match_spectra(a, b) < 1e-8, (ppc, k)


def test_usf_conservative_usl_dissipative_below_kcrit():
    for ppc in (1, 2, 6):
        an = ls.Analyser(10, ppc)
        for s in ("usf", "musl"):
            kc, _ = an.critical_fraction(s)
            lam = eig(an.reduced(s, 0.9 * kc))
            assert np.max(np.abs(np.abs(lam) - 1.0)) < 1e-9, (s, ppc)
        kc, _ = an.critical_fraction("usl")
        lam = eig(an.reduced("usl", 0.9 * kc))
        assert np.max(np.abs(lam)) < 1.0 + 1e-12
        assert np.min(np.abs(lam)) < 0.999  # some modes are damped


def test_iterating_the_literal_step_grows_only_above_kcrit():
    rng = np.random.default_rng(1)
    for s in SCHEMES:
        m = ls.Model(10, 2)
        an = ls.Analyser(10, 2)
        kc, _ = an.critical_fraction(s)
        for k, grows in ((0.97 * kc, False), (1.03 * kc, True)):
            v = rng.standard_normal(m.particles)
            sig = rng.standard_normal(m.particles)
            log_amp = 0.0
            for _ in range(3000):  # renormalised each step: log of the total amplification
                v, sig = m.step(s, k, v, sig)
                n = math.hypot(np.linalg.norm(v), np.linalg.norm(sig))
                log_amp += math.log(n)
                v, sig = v / n, sig / n
            assert (log_amp > math.log(1e3)) == grows, (s, k, log_amp)
            if not grows:
                assert log_amp < math.log(1e2), (s, k, log_amp)


def test_scan_step_does_not_miss_instability():
    for s in ("usl", "usf"):
        for ppc in (1, 4, 8):
            an = ls.Analyser(10, ppc)
            coarse = an.critical_fraction(s)[0]
            fine = an.critical_fraction(s, dk=2e-4)[0]
            assert abs(coarse - fine) < 1e-8, (s, ppc, coarse, fine)


def test_rho_map_shape_and_values():
    ks = [0.1, 0.7, 2.5]
    rm = ls.rho_map("usl", ks, [1, 2], elements=5)
    assert rm.shape == (2, 3)
    assert rm[0, 0] <= 1 + 1e-12 and rm[0, 2] > 1.1


def test_cli_help_and_csv():
    with contextlib.redirect_stdout(io.StringIO()) as out:
        try:
            ls.main(["--help"])
            raise AssertionError("--help did not exit")
        except SystemExit as e:
            assert e.code == 0
    assert "--schemes" in out.getvalue()
    with tempfile.TemporaryDirectory() as d:
        with contextlib.redirect_stdout(io.StringIO()):
            rc = ls.main(["--schemes", "usl,usf", "--ppc", "1-2", "--elements", "1", "--out", d])
        assert rc == 0
        with open(os.path.join(d, "predicted_critical.csv")) as fh:
            lines = fh.read().strip().splitlines()
        assert lines[0] == "scheme,particles_per_element,elements,k_crit"
        assert len(lines) == 5
        row = [l for l in lines if l.startswith("usl,1,1,")][0]
        assert abs(float(row.split(",")[3]) - 2 / math.sqrt(3)) < 1e-9
    with contextlib.redirect_stderr(io.StringIO()):
        assert ls.main(["--schemes", "foo", "--out", tempfile.gettempdir()]) == 2


def test_energy_ratio_one_element_usl_is_one_plus_k_squared():
    # USL, one element, one particle: v' = v, s' = k v after the first step from s = 0, so the
    # particle energy grows by 1 + k^2 (in c = rho = 1 units); it reaches 2 at k = 1, below
    # k_crit = 2/sqrt(3): an energy_growth guard with limit 2 would trip on a linearly stable run
    # (hence the default limit of 10).
    for k in (0.1, 0.5, 0.9):
        emax, _ = ls.energy_ratios("usl", k, 1, 1, 1)
        assert abs(emax - (1 + k * k)) < 1e-12, (k, emax)
    # a stable USF run keeps its energy bounded, an unstable one blows up
    assert ls.energy_ratios("usf", 1.0, 1, 20, 500)[0] < 1.5
    assert ls.energy_ratios("usl", 0.75, 1, 20, 2000)[0] > 1e3


def test_shape_values_partition_of_unity_and_derivatives():
    """Every shape: weights sum to one, reproduce x, derivatives are the weights' slopes."""
    x = 3.0 + (np.arange(97) + 0.37) * 4.0 / 97  # off the nodes and the GIMP kinks
    nodes = np.arange(0, 11)
    for shape in ("linear", "ugimp", "cpgimp", "bspline2", "bspline3"):
        w, d = ls.shape_values(shape, x[None, :] - nodes[:, None], 0.25)
        assert np.allclose(w.sum(axis=0), 1.0, atol=1e-14), shape
        assert np.allclose((w * nodes[:, None]).sum(axis=0), x, atol=1e-13), shape
        assert np.allclose(d.sum(axis=0), 0.0, atol=1e-13), shape
        h = 1e-6
        wp, _ = ls.shape_values(shape, x[None, :] + h - nodes[:, None], 0.25)
        wm, _ = ls.shape_values(shape, x[None, :] - h - nodes[:, None], 0.25)
        assert np.allclose((wp - wm) / (2 * h), d, atol=1e-6), shape


def test_wide_shapes_critical_fractions():
    """B-splines raise USL's limit above linear's; GIMP at rest (boxes inside their cells) equals
    linear, and a stretch that lets the end box enter the margin cell lowers it below 0.5 at 4 ppc
    (mpm1d measures 0.46, studies/shapes)."""
    lin = ls.Analyser(20, 4).critical_fraction("usl", dk=0.01)[0]
    b3 = ls.Analyser(20, 4, shape="bspline3").critical_fraction("usl", dk=0.01)[0]
    g0 = ls.Analyser(20, 4, shape="ugimp").critical_fraction("usl", dk=0.01)[0]
    g1 = ls.Analyser(20, 4, shape="ugimp", stretch=1e-6).critical_fraction("usl", dk=0.01)[0]
    assert b3 > lin + 0.3, (b3, lin)
    assert abs(g0 - lin) < 1e-9, (g0, lin)
    assert 0.45 < g1 < 0.5, g1


# ---------------------------------------------------------------------------------------------

def run_all() -> int:
    tests = [(n, f) for n, f in sorted(globals().items()) if n.startswith("test_") and callable(f)]
    passed = failed = 0
    for name, fn in tests:
        try:
            fn()
        except Exception as exc:  # noqa: BLE001 - report every failure
            failed += 1
            print(f"FAIL {name}: {type(exc).__name__}: {exc}")
        else:
            passed += 1
            print(f"ok   {name}")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(run_all())
