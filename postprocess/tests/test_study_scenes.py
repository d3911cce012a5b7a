"""The exact solutions of the scenes study (mpm1d_post.studies.scenes), written there independently of
the Fortran scenes, against values worked out by hand. The study's pipeline (the runs, the tables, the
figures) is tested by studies/scenes/test_scenes_study.py."""
from __future__ import annotations

import numpy as np
import pytest

from mpm1d_post.studies.scenes import column_displacement, composite_stress, impact_exact


def test_column_released_under_gravity():
    """u = u_s + sum a_n sin(beta_n x) cos(omega_n t), omega_n t = (2n - 1) pi c t / (2L): at t = 0 the
    series cancels the static sag u_s (the column starts undisplaced); at t = L/c every cosine is 0, so
    u = u_s; at t = 2L/c every cosine is -1, so u = 2 u_s (a load applied at once: twice the static sag);
    the fixed end stays at 0."""
    length, c, g = 25.0, 5000.0, 9.81
    x = np.linspace(0.0, length, 11)
    static = -(g / c ** 2) * (length * x - x ** 2 / 2)
    scale = np.max(np.abs(static))
    assert np.max(np.abs(column_displacement(x, 0.0, length, c, g))) < 1e-6 * scale
    assert column_displacement(x, length / c, length, c, g) == pytest.approx(static, abs=1e-6 * scale)
    assert column_displacement(x, 2 * length / c, length, c, g) == pytest.approx(2 * static, abs=1e-6 * scale)
    assert column_displacement(np.array([0.0]), 0.37 * length / c, length, c, g)[0] == 0.0


def test_composite_of_one_material_is_one_step_wave():
    """Two segments of one material: the driven end's step -rho c v travels at c, unchanged."""
    v, rho, modulus = 0.01, 1000.0, 16.0e6
    c = np.sqrt(modulus / rho)
    x = np.array([0.1, 0.5, 0.9, 1.1, 1.5])
    stress = composite_stress(x, 1.2 / c, [1.0, 1.0], [modulus, modulus], [rho, rho], v)  # front at x = 1.2
    assert stress == pytest.approx([-rho * c * v] * 4 + [0.0], abs=1e-12 * rho * c * v)


def test_composite_transmits_and_reflects_at_the_interface():
    """Stiff (16 MPa) then soft (1 MPa), one density: impedances z_a = 4 z_b. Past the interface the
    transmitted step is 2 z_b / (z_a + z_b) = 0.4 of the incident one; behind the reflected front the
    reflection (z_b - z_a) / (z_a + z_b) = -0.6 of it adds to the incident: 0.4 of it there too."""
    v, rho = 0.01, 1000.0
    ca, cb = np.sqrt(16.0e6 / rho), np.sqrt(1.0e6 / rho)
    incident = -rho * ca * v
    t = 1.0 / ca + 0.1 / cb  # the transmitted front at 1.1, the reflected one back at 1 - 0.1 ca/cb = 0.6
    stress = composite_stress(np.array([0.3, 0.8, 1.05, 1.2]), t, [1.0, 1.0], [16.0e6, 1.0e6], [rho, rho], v)
    assert stress == pytest.approx([incident, 0.4 * incident, 0.4 * incident, 0.0], rel=1e-12, abs=1e-9)


def test_impact_of_identical_bars():
    """Frictionless: the interface stress is -rho c v for 2L/c while bar 1 decelerates at c v / L, then
    the bars part (stress 0) and bar 1 moves at -v; stuck ('none'): the stress changes sign every 2L/c."""
    length, c, v = 1.0, 5000.0, 1.0
    period = 2 * length / c
    t = np.array([0.25, 0.5, 0.75, 1.5, 2.5]) * period
    u, stress = impact_exact(t, v, length, c, stick=False)
    a = c * v / length
    expected = [v * s - a * s ** 2 / 2 for s in t[:3]]
    expected += [v * period - a * period ** 2 / 2 - v * (s - period) for s in t[3:]]
    assert u == pytest.approx(expected, rel=1e-12)
    assert stress.tolist() == [-1.0, -1.0, -1.0, 0.0, 0.0]
    u, stuck = impact_exact(t, v, length, c, stick=True)
    assert stuck.tolist() == [-1.0, -1.0, -1.0, 1.0, -1.0]
    # stuck: bar 1 decelerates for 2L/c (to -v), then accelerates back: at 2L/c + s, u = u(2L/c) - v s + a s^2/2
    s = 0.5 * period
    assert u[3] == pytest.approx(v * period - a * period ** 2 / 2 - v * s + a * s ** 2 / 2, rel=1e-12)
