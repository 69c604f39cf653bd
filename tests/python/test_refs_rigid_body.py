"""Self-checks of tests/python/refs/rigid_body.py, the independent reference of RigidBody:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from refs import derive, rigid_body
from test_refs import rel_err

RNG = np.random.default_rng(20240611)


def test_rigid_body_box_and_rod_inertia():
    c = rigid_body.calculated()
    box = sorted(rigid_body.box_inertia(2.0, 0.3, 0.2, 0.1))
    assert np.allclose([c["I_1"], c["I_2"], c["I_3"]], box, rtol=1e-15, atol=0)
    assert abs(box[0] - 2.0 * 0.05 / 12) < 1e-16 and abs(box[2] - 2.0 * 0.13 / 12) < 1e-16
    # slender rod (radius a) of length L along x, pivot at one end
    M, L, a = 3.0, 1.2, 0.01
    p = rigid_body.params(M=M, I_xx=M * a * a / 2, I_yy=M * L * L / 12 + M * a * a / 4,
                          I_zz=M * L * L / 12 + M * a * a / 4, r_Cx=L / 2)
    IB = rigid_body.inertia_about_pivot(p)
    assert abs(IB[1, 1] - (M * L * L / 3 + M * a * a / 4)) < 1e-15 and IB[0, 0] == M * a * a / 2


def test_rigid_body_parallel_axis_against_point_masses():
    """I_C and I_B computed by definition sum m [(r.r)1 - r r^T] over a point cloud."""
    pts = RNG.normal(size=(40, 3)) * [0.3, 0.2, 0.1]
    ms = RNG.uniform(0.1, 1.0, 40)
    M = ms.sum()
    C = (ms[:, None] * pts).sum(0) / M
    B = np.array([0.05, -0.4, 0.2])

    def inertia(o):
        d = pts - o
        return sum(mi * (di @ di * np.eye(3) - np.outer(di, di)) for mi, di in zip(ms, d))
    IC, IBd = inertia(C), inertia(B)
    r = C - B
    p = rigid_body.params(M=M, I_xx=IC[0, 0], I_yy=IC[1, 1], I_zz=IC[2, 2], I_xy=IC[0, 1], I_xz=IC[0, 2],
                          I_yz=IC[1, 2], r_Cx=r[0], r_Cy=r[1], r_Cz=r[2])
    assert np.max(np.abs(rigid_body.inertia_about_pivot(p) - IBd)) < 1e-13
    assert IC[0, 1] < 0 or IC[0, 1] > 0  # products present; entry is -sum m x y
    d = pts - C
    assert abs(IC[0, 1] + (ms * d[:, 0] * d[:, 1]).sum()) < 1e-14


def test_rigid_body_principal_moments_with_products():
    p = rigid_body.params(I_xx=4.0, I_yy=4.0, I_zz=3.0, I_xy=-1.0)
    c = rigid_body.calculated(p)
    assert np.allclose([c["I_1"], c["I_2"], c["I_3"]], [3.0, 3.0, 5.0], rtol=1e-15, atol=1e-15)
    w, V = rigid_body.principal(p)
    assert abs(abs(V[:, 2] @ np.array([1, -1, 0]) / math.sqrt(2)) - 1) < 1e-14


def test_rigid_body_euler_equations_equal_lagrange_in_euler_angles():
    lag = derive.rigid_body_lagrange()
    p = rigid_body.params(I_xy=0.001, I_xz=-0.0005, I_yz=0.0008, r_Cx=0.03, r_Cy=-0.02, r_Cz=0.1)
    for _ in range(15):
        ang = [RNG.uniform(-3, 3), RNG.uniform(0.3, 2.8), RNG.uniform(-3, 3)]
        rates = RNG.normal(size=3) * 3
        u = {"tau_x": RNG.normal() * 0.1, "tau_y": RNG.normal() * 0.1, "tau_z": RNG.normal() * 0.1}
        d = lag(ang, rates, p, u)
        y = np.concatenate([d["w"], d["q"]])
        f = np.asarray(rigid_body.rhs(0.0, y, p, u))
        assert np.max(np.abs(f[:3] - d["w_dot"])) < 1e-12 * max(1.0, np.max(np.abs(d["w_dot"])))
        assert np.max(np.abs(f[3:] - d["q_dot"])) < 1e-13 * max(1.0, np.max(np.abs(d["q_dot"])))
        assert np.max(np.abs(f[3:] - derive.rigid_body_quaternion_rate(d["q"], d["w"]))) < 1e-14
        o = rigid_body.outputs_of(y, p)
        assert abs(o["E_kin"] + o["E_pot"] - d["E"]) < 1e-12 * max(1.0, abs(d["E"]))


def test_rigid_body_torque_free_conservation_and_intermediate_axis_flip():
    t = np.linspace(0.0, 20.0, 2001)
    r = rigid_body.simulate(None, None, t)
    H = np.vstack([r["H_X"], r["H_Y"], r["H_Z"]])
    assert np.max(np.abs(H - H[:, :1])) < 1e-10 * np.linalg.norm(H[:, 0])
    assert rel_err(r["E_kin"], np.full_like(t, r["E_kin"][0])) < 1e-10
    assert np.max(np.abs(r["q_norm"] - 1)) < 1e-10
    assert np.min(r["w_y"]) < -4.9 and np.max(r["w_y"]) > 4.9   # it flips (and back)


@pytest.mark.parametrize("axis", ["x", "z"])
def test_rigid_body_spin_about_extreme_axes_is_stable(axis):
    y0 = {"w_x": 0.01, "w_y": 0.01, "w_z": 0.01}
    y0["w_" + axis] = 5.0
    r = rigid_body.simulate(None, y0, np.linspace(0.0, 20.0, 2001))
    others = [a for a in "xyz" if a != axis]
    assert max(np.max(np.abs(r["w_" + a])) for a in others) < 0.05
    assert np.min(r["w_" + axis]) > 4.99


@pytest.mark.parametrize("Iz", [0.03, 0.005])   # oblate and prolate
def test_rigid_body_axisymmetric_torque_free_closed_form(Iz):
    p = rigid_body.params(I_xx=0.01, I_yy=0.01, I_zz=Iz)
    w0 = (0.3, -0.2, 4.0)
    t = np.linspace(0.0, 20.0, 2001)
    r = rigid_body.simulate(p, {"w_x": w0[0], "w_y": w0[1], "w_z": w0[2]}, t)
    wx, wy, wz = rigid_body.torque_free_axisymmetric(p, w0, t)
    assert np.max(np.abs(r["w_x"] - wx)) < 1e-9 and np.max(np.abs(r["w_y"] - wy)) < 1e-9
    assert np.max(np.abs(r["w_z"] - 4.0)) < 1e-12
    # direction: the angle of (w_x, w_y) advances at (I3 - I1)/I1 w_z (unwrapped phase slope)
    ang = np.unwrap(np.arctan2(r["w_y"], r["w_x"]))
    rate = (ang[-1] - ang[0]) / 20.0
    assert abs(rate - (Iz - 0.01) / 0.01 * 4.0) < 1e-8 * abs(rate)


def test_rigid_body_heavy_top_conserves_H_Z_and_energy():
    p = rigid_body.params(I_xy=0.001, r_Cx=0.02, r_Cy=0.01, r_Cz=0.15)
    q = rigid_body.quat_axis("x", 0.7)
    y0 = {"w_x": 1.0, "w_y": -2.0, "w_z": 30.0, "q_w": q[0], "q_x": q[1], "q_y": q[2], "q_z": q[3]}
    t = np.linspace(0.0, 10.0, 1001)
    r = rigid_body.simulate(p, y0, t)
    E = r["E_kin"] + r["E_pot"]
    assert np.ptp(r["E_pot"]) > 0.01                                   # gravity does work
    assert np.max(np.abs(E - E[0])) < 1e-10 * np.max(np.abs(r["E_kin"]))
    assert np.max(np.abs(r["H_Z"] - r["H_Z"][0])) < 1e-10 * np.max(np.abs(r["H_Z"]))
    assert np.ptp(r["H_X"]) > 1e-3                                     # H_X, H_Y are not conserved


@pytest.mark.parametrize("theta", [0.5, 2.0])
@pytest.mark.parametrize("root", [0, 1])
def test_rigid_body_steady_precession(theta, root):
    p = rigid_body.params(I_xx=0.01, I_yy=0.01, I_zz=0.02, r_Cz=0.1)
    w3 = 50.0
    Om = rigid_body.precession_rates(p, theta, w3)[root]
    IB = rigid_body.inertia_about_pivot(p)
    # the steady-precession condition M g d = Omega (I3 w3 - I1 Omega cos theta)
    assert abs(Om * (IB[2, 2] * w3 - IB[0, 0] * Om * math.cos(theta)) - p["M"] * p["g"] * 0.1) < 1e-12
    t = np.linspace(0.0, 5.0, 501)
    r = rigid_body.simulate(p, rigid_body.precession_state(p, theta, w3, Om), t)
    W, Q = rigid_body.precession_motion(theta, w3, Om, t)
    assert np.max(np.abs(np.vstack([r["w_x"], r["w_y"], r["w_z"]]) - W)) < 1e-9 * max(w3, abs(Om))
    assert np.max(np.abs(np.vstack([r["q_w"], r["q_x"], r["q_y"], r["q_z"]]) - Q)) < 1e-9
    # the nutation angle stays theta: body z in ground axes has Z-component cos theta
    zz = 1 - 2 * (r["q_x"] ** 2 + r["q_y"] ** 2)
    assert np.max(np.abs(zz - math.cos(theta))) < 1e-10


def test_rigid_body_slow_precession_approximation():
    p = rigid_body.params(I_xx=0.01, I_yy=0.01, I_zz=0.02, r_Cz=0.1)
    slow, fast = rigid_body.precession_rates(p, 0.5, 2000.0)
    approx = p["M"] * p["g"] * 0.1 / (0.02 * 2000.0)
    assert abs(slow - approx) < 1e-3 * approx and fast > 100 * slow
