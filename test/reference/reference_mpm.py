"""Independent, deliberately plain NumPy implementation of the 1-D MPM bar (USF, USL, MUSL).

Written from the conventions in README.md ("Algorithm"), not from the Fortran code: nodal
arrays are accumulated node by node with np.add.at, shape functions are recomputed from the
positions, u_cm is sum m (x - X) / sum m. Used by test/reference/check_reference.py to confirm that
mpm1d's errors agree with a second implementation to round-off.
"""
import math
import numpy as np


def run(scheme, elements, ppc, dt_fraction, periods=2.0, length=25.0, E=200e9, rho=7800.0, v0=0.1, mode=1, margin=None):
    """margin: empty cells beyond the free end x = L (None: the end's amplitude v0/omega in cells,
    rounded up, plus 2, as README.md says)."""
    c = math.sqrt(E / rho)
    dx = length / elements
    dt = dt_fraction * dx / c
    beta = (2 * mode - 1) * math.pi / (2 * length)
    omega = beta * c
    end = periods * 2 * math.pi / omega
    ratio = end / dt
    steps = round(ratio)
    if abs(ratio - steps) > 1e-9 * max(1.0, ratio):
        steps = math.ceil(ratio)
    amp = v0 / (omega * beta * length)
    if margin is None:
        margin = math.ceil(abs(v0) / omega / dx) + 2

    sub = dx / ppc
    X = np.array([e * dx + (k + 0.5) * sub for e in range(elements) for k in range(ppc)])
    x = X.copy()
    m = np.full(X.size, rho * sub)
    V0 = np.full(X.size, sub)
    v = v0 * np.sin(beta * X)
    s = np.zeros(X.size)
    J = np.ones(X.size)
    nn = elements + margin + 1
    tol = 1e-12 * m[0]

    def shape(xp):
        e = np.floor(xp / dx).astype(int)
        e = np.minimum(e, elements + margin - 1)
        xi = xp / dx - e
        return e, 1 - xi, xi

    def nodal(e, n0, n1, q):
        out = np.zeros(nn)
        np.add.at(out, e, n0 * q)
        np.add.at(out, e + 1, n1 * q)
        return out

    def force(e):
        f = np.zeros(nn)
        sv = s * J * V0
        np.add.at(f, e, sv / dx)        # -dN_left = +1/dx
        np.add.at(f, e + 1, -sv / dx)   # -dN_right = -1/dx
        f[0] = 0.0
        return f

    def vel(p, mass):
        out = np.where(mass > tol, p / np.where(mass > tol, mass, 1.0), 0.0)
        out[0] = 0.0
        return out

    ucm, err = [0.0], 0.0
    energy = [np.sum(0.5 * m * v * v)]
    for n in range(1, steps + 1):
        e, n0, n1 = shape(x)
        mass = nodal(e, n0, n1, m)
        mom = nodal(e, n0, n1, m * v)
        mom[0] = 0.0
        if scheme == 'usf':
            vi = vel(mom, mass)
            de = dt * (vi[e + 1] - vi[e]) / dx
            s = s + E * de
            J = J * (1 + de)
        f = force(e)
        mom = mom + dt * f
        mom[0] = 0.0
        a = vel(f, mass)
        vi = vel(mom, mass)
        v = v + dt * (n0 * a[e] + n1 * a[e + 1])
        x = x + dt * (n0 * vi[e] + n1 * vi[e + 1])
        if scheme in ('usl', 'musl'):
            if scheme == 'musl':
                mom = nodal(e, n0, n1, m * v)
                mom[0] = 0.0
                vi = vel(mom, mass)
            de = dt * (vi[e + 1] - vi[e]) / dx
            s = s + E * de
            J = J * (1 + de)
        u = np.sum(m * (x - X)) / np.sum(m)
        ucm.append(u)
        err = max(err, abs(u - amp * math.sin(omega * n * dt)))
        energy.append(np.sum(0.5 * m * v * v) + np.sum(0.5 * s * s * J * V0 / E))
    return dict(max_error=err, relative_error=err / abs(amp), steps=steps, dt=dt, ucm=np.array(ucm),
                energy=np.array(energy))


if __name__ == '__main__':
    for scheme in ('usf', 'usl', 'musl'):
        r = run(scheme, 20, 1, 0.1)
        print(scheme, r['max_error'], r['relative_error'], r['steps'])
