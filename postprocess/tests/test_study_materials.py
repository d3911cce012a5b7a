"""The materials study's own exact solutions of the plastic wave (mpm1d_post.studies.materials) against hand
values and the Rankine-Hugoniot conditions they must satisfy, and its critical time step. The study's
pipeline is tested by studies/materials/test_materials_study.py."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mpm1d_post.loader import Sweep
from mpm1d_post.studies.materials import critical, finite_strain, small_strain, stress_profile

# E = 4, rho = 1, sigma_y = 1, H = 4/3: c_e = 2, E_t = E H / (E + H) = 1, c_p = 1, v1 = sigma_y / (rho c_e) = 0.5
E, RHO, SY, H = 4.0, 1.0, 1.0, 4.0 / 3.0


def test_small_strain_fronts_by_hand():
    """V = 1.5: the precursor carries sigma_y = 1 at c_e = 2, the plastic front 1 + rho c_p (V - v1) = 2 at c_p = 1."""
    front = small_strain(E, RHO, SY, H, 1.5)
    assert front == pytest.approx(dict(c1=2.0, c2=1.0, s1=1.0, s2=2.0, v1=0.5), rel=1e-14)
    # below the yield velocity one elastic wave of rho c_e V
    assert small_strain(E, RHO, SY, H, 0.25) == pytest.approx(dict(c1=2.0, c2=0.0, s1=0.5, s2=0.5, v1=0.25))


def test_finite_strain_shocks_satisfy_rankine_hugoniot():
    """Each shock: [v] = U [F] and [sigma] = rho U^2 [F], with sigma = E ln F to F1 = exp(-sigma_y / E), then
    -(sigma_y + E_t ln(F1 / F)); and the plastic state ends at V."""
    V = 1.5
    fs = finite_strain(E, RHO, SY, H, V)
    f1 = math.exp(-SY / E)
    assert fs['s1'] == pytest.approx(RHO * fs['c1'] ** 2 * (1 - f1), rel=1e-12)   # [sigma] across the precursor
    assert fs['v1'] == pytest.approx(fs['c1'] * (1 - f1), rel=1e-12)              # [v] across it
    f2 = f1 / math.exp((fs['s2'] - SY) / 1.0)                                      # E_t = 1: s2 = 1 + ln(F1/F2)
    assert fs['s2'] - fs['s1'] == pytest.approx(RHO * fs['c2'] ** 2 * (f1 - f2), rel=1e-9)
    assert V - fs['v1'] == pytest.approx(fs['c2'] * (f1 - f2), rel=1e-9)
    # compression stiffens Hencky's law: the plastic stress lies above the small-strain one
    assert fs['s2'] > small_strain(E, RHO, SY, H, V)['s2']


def test_finite_strain_tends_to_small_strain():
    """At small velocity (an elastic wave) the shock solution is the small-strain one."""
    V = 1e-6
    fs, ss = finite_strain(E, RHO, SY, H, V), small_strain(E, RHO, SY, H, V)
    assert fs['s1'] == pytest.approx(ss['s1'], rel=1e-5) and fs['c1'] == pytest.approx(ss['c1'], rel=1e-5)


def test_stress_profile_of_two_fronts():
    front = dict(c1=2.0, c2=1.0, s1=1.0, s2=2.0)
    x = np.array([0.5, 1.5, 2.5])
    assert stress_profile(front, x, 1.0).tolist() == [-2.0, -1.0, 0.0]


def test_critical_time_step_is_the_first_that_stops():
    cases = {'scheme': np.array(['usl'] * 4 + ['usf'] * 3), 'shape': np.array(['linear'] * 7),
             'dt_fraction': np.array([0.6, 0.2, 0.8, 0.4, 0.2, 0.4, 0.6]), 'status': np.array([1, 0, 1, 0, 0, 0, 0])}
    sweep = Sweep(paths=['s.h5'], code_versions=['test'], config={}, sweep=[{}], cases=cases)
    assert critical(sweep, 'usl', 'linear') == 0.6
    assert math.isnan(critical(sweep, 'usf', 'linear'))
