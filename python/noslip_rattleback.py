"""Independent reference for scenes/rattleback.json (docs/contact.md §"The rattleback"): the
rattleback as a rigid body rolling WITHOUT SLIPPING on the plane y = 0, the classic no-slip model
of the rattleback literature, integrated by classical RK4 in numpy. It shares no code with
rigidref: a different contact law (no slip, no penetration, energy conserved, where rigidref
solves a velocity-level frictional contact problem), a different integrator and language.

    python3 python/noslip_rattleback.py [STEP]     # both spins, both signs of the tilt

Frame: world y up; body frame at the centre of mass; R maps body to world; omega is the world
angular velocity. The contact shape is the ellipsoid (q - c)^T A^-2 (q - c) = 1 (body frame).

Contact point. The lowest point of the ellipsoid is q(u) = c + A^2 u / |A u| with
u = R^T (-y): r = R q(u) is the world vector from the centre of mass to it.

No slip. The material point at r has zero velocity: v = -omega x r. The contact force F satisfies
m dv/dt = F - m g y, and d(J omega)/dt = r x F about the centre of mass, with J = R J0 R^T.
Differentiating the constraint, dv/dt = -domega x r - omega x rdot, where rdot is the total
derivative of the (geometric) contact vector: rdot = omega x r + R Q R^T (omega x y) with
Q = dq/du = (A^2 - A^2 u u^T A^2 / |Au|^2) / |Au| (u moves as du/dt = R^T (omega x y)).
Eliminating F:

  (J + m [(r.r) I - r r^T]) domega = -omega x J omega - m r x (omega x rdot) + m g r x y,

and dx/dt = v = -omega x r, dR/dt = [omega]x R. The energy
E = m v^2/2 + omega.J omega/2 + m g x_y is conserved (the contact does no work).
"""

import numpy as np


def skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


class Rattleback:
    def __init__(self, semi_axes, centre, mass, inertia, g=9.81):
        self.A2 = np.diag(np.asarray(semi_axes, float) ** 2)
        self.A = np.diag(np.asarray(semi_axes, float))
        self.c = np.asarray(centre, float)
        self.m = mass
        self.J0 = np.asarray(inertia, float)
        self.g = g

    def contact(self, R):
        """World vector r from the centre of mass to the lowest point, and the Jacobian dq/du."""
        u = R.T @ np.array([0.0, -1.0, 0.0])
        au = self.A @ u
        n = np.linalg.norm(au)
        q = self.c + self.A2 @ u / n
        Q = (self.A2 - np.outer(self.A2 @ u, self.A2 @ u) / n**2) / n
        return R @ q, Q

    def derivative(self, state):
        x, v, R, w = state
        r, Q = self.contact(R)
        y = np.array([0.0, 1.0, 0.0])
        J = R @ self.J0 @ R.T
        rdot = np.cross(w, r) + R @ Q @ R.T @ np.cross(w, y)
        M = J + self.m * (r @ r * np.eye(3) - np.outer(r, r))
        rhs = -np.cross(w, J @ w) - self.m * np.cross(r, np.cross(w, rdot)) + self.m * self.g * np.cross(r, y)
        dw = np.linalg.solve(M, rhs)
        return (-np.cross(w, r), -np.cross(dw, r) - np.cross(w, rdot), skew(w) @ R, dw)

    def energy(self, state):
        x, v, R, w = state
        J = R @ self.J0 @ R.T
        return 0.5 * self.m * v @ v + 0.5 * w @ J @ w + self.m * self.g * x[1]

    def start(self, omega):
        R = np.eye(3)
        r, _ = self.contact(R)
        w = np.asarray(omega, float)
        return (-r.copy(), -np.cross(w, r), R, w)


def rk4(body, state, h):
    def add(s, d, k):
        return tuple(a + k * b for a, b in zip(s, d))

    k1 = body.derivative(state)
    k2 = body.derivative(add(state, k1, h / 2))
    k3 = body.derivative(add(state, k2, h / 2))
    k4 = body.derivative(add(state, k3, h))
    new = tuple(a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(state, k1, k2, k3, k4))
    x, v, R, w = new
    U, _, Vt = np.linalg.svd(R)  # keep R a rotation
    return (x, v, U @ Vt, w)


def rattleback(delta_deg=0.8):
    """The rattleback of scenes/rattleback.json (scenes/make_rattleback.py): semi-axes 0.20, 0.02
    (vertical), 0.03 m, centre 1 cm above the centre of mass, 1 kg, principal moments A = 2e-4
    (x), C = 1.7e-3 (y), B = 1.6e-3 (z) kg m^2 turned by delta about +y."""
    A, B, C = 2e-4, 1.6e-3, 1.7e-3
    d = np.radians(delta_deg)
    Ry = np.array([[np.cos(d), 0, np.sin(d)], [0, 1, 0], [-np.sin(d), 0, np.cos(d)]])
    J0 = Ry @ np.diag([A, C, B]) @ Ry.T
    return Rattleback([0.2, 0.02, 0.03], [0, 0.01, 0], 1.0, J0)


def simulate(body, omega0, t_end, h):
    s = body.start(omega0)
    e0 = body.energy(s)
    out = []
    n = int(round(t_end / h))
    for k in range(1, n + 1):
        s = rk4(body, s, h)
        out.append((k * h, s[3][1], body.energy(s) - e0, s[1] + np.cross(s[3], body.contact(s[2])[0])))
    return out


def first_reversal(series, spin0, threshold=0.1):
    for t, wy, _, _ in series:
        if wy * np.sign(spin0) < -threshold:
            return t
    return None


if __name__ == "__main__":
    import sys
    h = float(sys.argv[1]) if len(sys.argv) > 1 else 5e-4
    for delta in (0.8, -0.8):
        for spin in (-3.0, 3.0):
            body = rattleback(delta)
            ser = simulate(body, [0.05, spin, 0.05], 10.0, h)
            drift = max(abs(e) for _, _, e, _ in ser)
            slip = max(np.linalg.norm(s) for *_, s in ser)
            print(f"delta {delta:+.1f} deg, spin {spin:+.0f}: reversal {first_reversal(ser, spin)}, "
                  f"w_y(10 s) {ser[-1][1]:+.3f}, |dE| <= {drift:.2e} J, slip <= {slip:.1e} m/s", flush=True)
