"""Independent NumPy implementations of the MPM methods beyond the classic ones (docs/theory.md, "The
cures"): the total-Lagrangian formulation, CPDI in 1-D, XPIC(m), FMPM(k) and ASFLIP, with the classic
FLIP and PIC beside them, on the vibrating bar and the manufactured large-strain solution.

Written from the papers and from the method statements of issue 37 (the conventions that docs/theory.md
states), not from mpm1d's Fortran. It is deliberately plain and different in form: every step builds the
dense matrices S (particles x nodes, the weights N_I(x_p)) and G (their gradients) and works with them
as the papers write the methods,
  m_I = S^T m,  p_I = S^T (m v),  f_I = -G^T (sigma V) + S^T (m b),
  A = M_L^-1 S^T diag(m) S          (the particle projection of XPIC and FMPM),
so that XPIC's v* is a binomial sum of powers of A, FMPM's v_k a Neumann series, CPDI's weights the
mean of the hat at the domain's corners, and the total-Lagrangian matrices are built once from the
reference positions. Used by check_reference.py: first each method against facts it must satisfy
(self_checks), then mpm1d against these runs to round-off.

References (docs/theory.md has the full entries):
  total-Lagrangian MPM  de Vaucorbeil, Nguyen, Hutchinson 2020, doi:10.1016/j.cma.2019.112783
  CPDI                  Sadeghirad, Brannon, Burghardt 2011, doi:10.1002/nme.3110;
                        CPDI2: Sadeghirad, Brannon, Guilkey 2013, doi:10.1002/nme.4526
  XPIC(m)               Hammerquist, Nairn 2017, doi:10.1016/j.cma.2017.01.035
  FMPM(k)               Nairn, Hammerquist 2021, doi:10.1016/j.cma.2021.113667
  ASFLIP                Fei, Guo, Wu, Huang, Gao 2021, doi:10.1145/3450626.3459678
"""
import math

import numpy as np

# ASFLIP's separation threshold on ln J^(n+1) (Fei et al. 2021: a particle whose volume would shrink by
# more than this is in contact and moves with the grid; one that is not keeps its own velocity's offset)
SEPARATION_THRESHOLD = -1.0e-3


def hat(points, dx, nodes):
    """Hat functions of the uniform grid x_I = I dx, I = 0 .. nodes - 1, at `points`: matrices N (points x
    nodes) and dN/dx. A point on a node belongs to the cell to its right, the grid's last node to the
    last cell."""
    s = np.asarray(points, dtype=float) / dx
    cell = np.minimum(np.floor(s).astype(int), nodes - 2)
    if np.any(cell < 0) or np.any(s > nodes - 1):
        raise ValueError('a point left the grid')
    xi = s - cell
    rows = np.arange(s.size)
    n = np.zeros((s.size, nodes))
    g = np.zeros((s.size, nodes))
    n[rows, cell] = 1.0 - xi
    n[rows, cell + 1] = xi
    g[rows, cell] = -1.0 / dx
    g[rows, cell + 1] = 1.0 / dx
    return n, g


def cpdi(corners, dx, nodes, n=None):
    """CPDI in 1-D: particle p's domain is [corners[p], corners[p + 1]]; its weights are the mean of the hat
    over the domain with the hat replaced by its linear interpolant between the corners,
    S_I = (N_I(x1) + N_I(x2))/2, and its gradients the exact mean of dN_I/dx over the domain,
    G_I = (N_I(x2) - N_I(x1))/(x2 - x1) (Sadeghirad et al. 2011, eqs. for the 1-D case). `n`: the hat at
    the corners, when the caller has it."""
    if n is None:
        n, _ = hat(corners, dx, nodes)
    length = np.diff(corners)
    return 0.5 * (n[:-1] + n[1:]), (n[1:] - n[:-1]) / length[:, None]


def update_law(law, youngs_modulus, stress, volume_ratio, dstrain):
    """One step of the law for the strain increment d eps (the log-strain increment dt dv/dx, in 1-D
    dF/F), as docs/theory.md states the laws per step: hencky sigma += E d eps, linear sigma += (E +
    sigma) d eps (sigma = E (J - 1) exactly), and J <- J (1 + d eps) for both."""
    if law == 'hencky':
        stress = stress + youngs_modulus * dstrain
    elif law == 'linear':
        stress = stress + (youngs_modulus + stress) * dstrain
    else:
        raise ValueError(law)
    return stress, volume_ratio * (1.0 + dstrain)


def xpic_velocity(apply_a, v, order):
    """XPIC(m)'s grid velocity v* = sum_{k=1..m} (-1)^(k+1) C(m, k) A^(k-1) v (Hammerquist and Nairn 2017)."""
    total = np.zeros_like(v)
    power = v.copy()  # A^(k-1) v
    for k in range(1, order + 1):
        total += (-1) ** (k + 1) * math.comb(order, k) * power
        power = apply_a(power)
    return total


def fmpm_velocity(apply_a, to_velocity, momentum, order):
    """FMPM(k)'s velocity of a grid momentum q: v_k(q) = sum_{r<k} (I - A)^r M_L^-1 q (Nairn and Hammerquist
    2021), the partial Neumann series of A^-1 M_L^-1 q."""
    term = to_velocity(momentum)
    total = term.copy()
    for _ in range(1, order):
        term = term - apply_a(term)
        total += term
    return total


class Scene:
    """The vibrating bar (fixed at x = 0, free at x = L, v = v0 sin(beta x), exact u_cm) or the manufactured
    solution u = A sin(kX) sin(wt) (both ends fixed, the body force of the law, error the mass-weighted RMS
    of x - X - u): as docs/theory.md and docs/user-guide.md state them."""

    def __init__(self, kind, length, youngs_modulus, density, v0, amplitude, law):
        self.kind, self.length, self.law = kind, length, law
        self.c = math.sqrt(youngs_modulus / density)
        if kind == 'vibrating_bar':
            self.beta = math.pi / (2 * length)
            self.omega = self.beta * self.c
            self.period = 2 * math.pi / self.omega
            self.ucm_amplitude = v0 / (self.omega * self.beta * length)
            self.v0 = v0
        elif kind == 'manufactured':
            self.k = 2 * math.pi / length
            self.omega = math.pi * self.c / length
            self.period = 2 * length / self.c
            self.amplitude = amplitude
            self.ucm_amplitude = amplitude
        else:
            raise ValueError(kind)

    def initial_velocity(self, X):
        if self.kind == 'vibrating_bar':
            return self.v0 * np.sin(self.beta * X)
        return self.amplitude * self.omega * np.sin(self.k * X)

    def body_force(self, X, t):
        """b(X, t) = u_tt - (1/rho0) dP/dX for the manufactured solution (zero for the bar)."""
        if self.kind == 'vibrating_bar':
            return np.zeros_like(X)
        s = math.sin(self.omega * t)
        f = 1.0 + self.amplitude * self.k * np.cos(self.k * X) * s
        stiffness = self.c ** 2 * self.k ** 2 * (1.0 if self.law == 'linear' else 1.0 / f)
        return self.amplitude * np.sin(self.k * X) * s * (-self.omega ** 2 + stiffness)

    def error(self, x, X, m, t):
        """The scene's error measure at time t and the centre-of-mass displacement."""
        ucm = np.sum(m * (x - X)) / np.sum(m)
        if self.kind == 'vibrating_bar':
            return abs(ucm - self.ucm_amplitude * math.sin(self.omega * t)), ucm
        u = self.amplitude * np.sin(self.k * X) * math.sin(self.omega * t)
        return math.sqrt(np.sum(m * (x - X - u) ** 2) / np.sum(m)), ucm


def run(kind='vibrating_bar', scheme='usl', elements=20, ppc=2, dt_fraction=0.1, periods=1.0, law='linear',
        shape='linear', transfer='flip', formulation='updated', xpic_order=2, fmpm_order=2, asflip_alpha=0.99,
        length=25.0, youngs_modulus=200e9, density=7800.0, v0=0.1, amplitude=0.025, margin=None):
    """One run; returns its max error, relative error, steps, dt, the u_cm history and, for the checks,
    the final state and the weights of the last step."""
    scene = Scene(kind, length, youngs_modulus, density, v0, amplitude, law)
    dx = length / elements
    dt = dt_fraction * dx / scene.c
    ratio = periods * scene.period / dt
    steps = round(ratio)
    if abs(ratio - steps) > 1e-9 * max(1.0, ratio):
        steps = math.ceil(ratio)
    if margin is None:  # the free end's reach in cells plus two (the manufactured scene has none)
        margin = math.ceil(abs(v0) / scene.omega / dx) + 2 if kind == 'vibrating_bar' else 0
    nodes = elements + margin + 1
    fixed = [0] if kind == 'vibrating_bar' else [0, elements]

    sub = dx / ppc
    X = np.array([e * dx + (k + 0.5) * sub for e in range(elements) for k in range(ppc)])
    x = X.copy()
    m = np.full(X.size, density * sub)
    V0 = np.full(X.size, sub)
    v = scene.initial_velocity(X)
    stress = np.zeros(X.size)
    J = np.ones(X.size)
    corners = np.concatenate(([X[0] - 0.5 * V0[0]], X + 0.5 * V0))
    empty = 1e-12 * m[0]
    total = formulation == 'total'

    def weights():
        if shape == 'linear':
            return hat(X if total else x, dx, nodes)
        if shape == 'cpdi':
            return cpdi(corners, dx, nodes, n_corner)
        raise ValueError(shape)

    n_corner = None
    if total:  # the reference configuration's weights, once
        S, G = weights()

    history, worst = [0.0], 0.0
    for n in range(1, steps + 1):
        t = (n - 1) * dt
        if not total:
            if shape == 'cpdi':
                n_corner, _ = hat(corners, dx, nodes)
            S, G = weights()
        mass = S.T @ m
        heavy = mass > empty

        def to_velocity(q):
            out = np.where(heavy, q / np.where(heavy, mass, 1.0), 0.0)
            out[fixed] = 0.0
            return out

        def momentum_of(vp):
            q = S.T @ (m * vp)
            q[fixed] = 0.0
            return q

        def apply_a(w):  # A w = M_L^-1 S^T diag(m) S w, the fixed nodes held
            return to_velocity(S.T @ (m * (S @ w)))

        def grid_velocity(q):  # a velocity from a momentum: FMPM filters every one
            return fmpm_velocity(apply_a, to_velocity, q, fmpm_order) if transfer == 'fmpm' else to_velocity(q)

        def volume():  # the volume the internal force integrates over
            if total:
                return V0
            if shape == 'cpdi':
                return np.diff(corners)
            return J * V0

        def strain_update(velocity):
            nonlocal stress, J
            rate = G @ velocity
            dstrain = dt * rate / J if total else dt * rate  # total: dF = dt sum_I v_I dN_I/dX, d eps = dF/F
            stress, J = update_law(law, youngs_modulus, stress, J, dstrain)

        external = S.T @ (m * scene.body_force(X, t))
        q = momentum_of(v)
        v_start = to_velocity(q)  # v^n, before the force update
        J_start = J.copy()
        if scheme == 'usf':
            strain_update(grid_velocity(q))
        force = -(G.T @ (stress * volume())) + external
        force[fixed] = 0.0
        q_updated = q + dt * force
        q_updated[fixed] = 0.0
        acceleration = to_velocity(force)
        v_updated = to_velocity(q_updated)

        v_old = v.copy()
        if transfer == 'flip':
            v = v + dt * (S @ acceleration)
            move = S @ v_updated
        elif transfer == 'pic':
            v = S @ v_updated
            move = S @ v_updated
        elif transfer == 'xpic':
            v = S @ xpic_velocity(apply_a, v_start, xpic_order) + dt * (S @ acceleration)
            move = S @ v_updated
        elif transfer == 'fmpm':
            filtered = grid_velocity(q_updated)
            v = S @ filtered
            move = S @ filtered
        elif transfer == 'asflip':
            v_pic = S @ v_updated
            offset = v_old - S @ v_start
            separating = np.log(J_start) + dt * (G @ v_updated) >= SEPARATION_THRESHOLD
            v = v_pic + asflip_alpha * offset
            move = v_pic + np.where(separating, asflip_alpha * offset, 0.0)
        else:
            raise ValueError(transfer)

        if shape == 'cpdi' and not total:  # the corners move with the grid velocity the particles move with
            corner_velocity = grid_velocity(q_updated) if transfer == 'fmpm' else v_updated
            corners = corners + dt * (n_corner @ corner_velocity)
            x = 0.5 * (corners[:-1] + corners[1:])
        else:
            x = x + dt * move

        if scheme == 'usl':
            strain_update(grid_velocity(q_updated))
        elif scheme == 'musl':
            strain_update(grid_velocity(momentum_of(v)))
        elif scheme != 'usf':
            raise ValueError(scheme)

        error, ucm = scene.error(x, X, m, n * dt)
        worst = max(worst, error)
        history.append(ucm)
    return dict(max_error=worst, relative_error=worst / abs(scene.ucm_amplitude), steps=steps, dt=dt,
                ucm=np.array(history), x=x, v=v, stress=stress, volume_ratio=J, corners=corners, S=S, G=G,
                grid_x=dx * np.arange(nodes))


def order(errors, sizes):
    """Observed orders of convergence between successive meshes."""
    return [math.log(errors[i] / errors[i + 1]) / math.log(sizes[i + 1] / sizes[i]) for i in range(len(errors) - 1)]


def self_checks():
    """Each method against facts it must satisfy, on its own: XPIC(1), FMPM(1) and ASFLIP with alpha = 0 are
    PIC; XPIC's v* and FMPM's v_k are one polynomial in A (two independent forms); the total-Lagrangian bar
    of the linear law and CPDI converge at second order; CPDI's weights are a partition of unity that
    reproduces linear fields, their gradients the derivatives of the weights along the domain. Returns a
    list of (name, passed, detail)."""
    results = []

    def check(name, passed, detail):
        results.append((name, bool(passed), detail))

    base = dict(elements=10, ppc=2, dt_fraction=0.2, periods=0.5, law='hencky', v0=50.0)
    for scheme in ('usf', 'usl', 'musl'):
        pic = run(scheme=scheme, transfer='pic', **base)
        amp = pic['max_error'] / pic['relative_error']
        for transfer, extra in (('xpic', dict(xpic_order=1)), ('fmpm', dict(fmpm_order=1)),
                                ('asflip', dict(asflip_alpha=0.0))):
            other = run(scheme=scheme, transfer=transfer, **extra, **base)
            diff = np.max(np.abs(other['ucm'] - pic['ucm'])) / amp
            check(f'{transfer} at order 1 / alpha 0 is PIC ({scheme})', diff <= 1e-12, f'history diff {diff:.1e}')
        flip = run(scheme=scheme, transfer='flip', **base)
        diff = np.max(np.abs(flip['ucm'] - pic['ucm'])) / amp
        check(f'PIC differs from FLIP ({scheme}: the checks above can fail)', diff > 1e-6, f'history diff {diff:.1e}')

    # v* of XPIC(m) on v and v_m of FMPM(m) on M v are sum_{r<m} (I - A)^r v: a binomial sum and a Neumann
    # series; and A v* = (I - (I - A)^m) v
    state = run(scheme='usl', transfer='flip', **base)
    S, m = state['S'], np.full(state['x'].size, 7800.0 * 25.0 / 20)
    mass = S.T @ m
    heavy = mass > 0

    def to_velocity(q):
        out = np.where(heavy, q / np.where(heavy, mass, 1.0), 0.0)
        out[0] = 0.0
        return out

    def apply_a(w):
        return to_velocity(S.T @ (m * (S @ w)))

    rng = np.random.default_rng(7)
    w = to_velocity(mass * rng.standard_normal(mass.size))
    for order_m in (1, 2, 3, 5, 8):
        vstar = xpic_velocity(apply_a, w, order_m)
        vk = fmpm_velocity(apply_a, to_velocity, mass * w, order_m)
        residual = w.copy()
        for _ in range(order_m):
            residual = residual - apply_a(residual)
        identity = np.max(np.abs(apply_a(vstar) - (w - residual)))
        diff = np.max(np.abs(vstar - vk))
        scale = np.max(np.abs(w))
        check(f'XPIC({order_m}) v* = FMPM({order_m}) v_k = sum (I - A)^r v', diff <= 1e-12 * scale and
              identity <= 1e-12 * scale, f'difference {diff / scale:.1e}, A v* - (I - (I - A)^m) v {identity / scale:.1e}')

    # second order: the linear-law bar, USL, FLIP, 2 particles per element, dt = 0.1 dx/c, one period
    sizes = [16, 32, 64]
    for name, extra in (('total-Lagrangian', dict(formulation='total')), ('CPDI', dict(shape='cpdi'))):
        errors = [run(elements=n, ppc=2, dt_fraction=0.1, periods=1.0, law='linear', **extra)['relative_error']
                  for n in sizes]
        orders = order(errors, sizes)
        check(f'{name} bar converges at order 2', all(1.8 <= p <= 2.2 for p in orders),
              'errors ' + ', '.join(f'{e:.3e}' for e in errors) + '; orders ' + ', '.join(f'{p:.2f}' for p in orders))

    # second order at large strain (F from 0.69 to 1.31): the manufactured solution, both laws; the
    # updated-Lagrangian hat does not converge there
    large = dict(kind='manufactured', length=1.0, youngs_modulus=1e7, density=1000.0, amplitude=0.05, ppc=2,
                 dt_fraction=0.1, periods=0.5)
    for name, law, extra in (('total-Lagrangian', 'linear', dict(formulation='total')),
                             ('total-Lagrangian', 'hencky', dict(formulation='total')),
                             ('CPDI', 'hencky', dict(shape='cpdi')), ('hat (updated)', 'hencky', {})):
        errors = [run(elements=n, law=law, **large, **extra)['relative_error'] for n in sizes]
        orders = order(errors, sizes)
        converges = all(1.8 <= p <= 2.2 for p in orders)
        check(f'{name} manufactured solution ({law}) ' + ('diverges (the checks above can fail)' if not extra else
                                                          'converges at order 2'),
              converges == bool(extra), 'errors ' + ', '.join(f'{e:.3e}' for e in errors) + '; orders ' +
              ', '.join(f'{p:.2f}' for p in orders))

    # CPDI's weights after a large-strain run
    big = run(kind='manufactured', shape='cpdi', elements=8, ppc=2, dt_fraction=0.2, periods=0.25, law='hencky',
              length=1.0, youngs_modulus=1e7, density=1000.0, amplitude=0.05)
    x, corners, grid_x = big['x'], big['corners'], big['grid_x']
    S, G = cpdi(corners, grid_x[1], grid_x.size)
    n_corner, _ = hat(corners, grid_x[1], grid_x.size)
    stretch = np.diff(corners) / (1.0 / 16)
    checks = {
        'partition of unity': np.max(np.abs(S.sum(axis=1) - 1.0)),
        'gradients sum to zero': np.max(np.abs(G.sum(axis=1))) * grid_x[1],
        'linear field reproduced (sum S_I x_I = the centre)': np.max(np.abs(S @ grid_x - x)),
        'gradient of a linear field (sum G_I x_I = 1)': np.max(np.abs(G @ grid_x - 1.0)),
        'G (x2 - x1) = N(x2) - N(x1)': np.max(np.abs(G * np.diff(corners)[:, None] - np.diff(n_corner, axis=0))),
    }
    for what, value in checks.items():
        check(f'CPDI: {what}', value <= 1e-13, f'{value:.1e} (domains stretched {stretch.min():.3f} to {stretch.max():.3f})')
    check('CPDI: the domains tile the body (the corners stay ordered, the ends at the fixed walls)',
          np.all(np.diff(corners) > 0) and corners[0] == 0.0 and abs(corners[-1] - 1.0) <= 1e-15,
          f'first corner {corners[0]:.1e}, last {corners[-1]:.17g}')
    return results


if __name__ == '__main__':
    for name, passed, detail in self_checks():
        print(f"{'ok  ' if passed else 'FAIL'} {name}: {detail}")
