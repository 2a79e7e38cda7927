"""Float reference of the whole method in double precision (the ideal algorithm).

Eqs. 5-7 (RLS with exponential forgetting, lambda = 1/(1 + 2**-k) as in the gateware),
Eq. 8 (parameters, with asin and sqrt), Eq. 9 (correction), then the ideal interpolation:
the angle by atan2 (no table) and an x4 count of the n-th order quadrants. It takes the
same samples for estimation as the gateware when given their indices (`update_idx`), so
the bit-true model can be compared with it coefficient by coefficient; by default it
updates on every sample.
"""
import numpy as np


def extract(theta):
    """Eq. 8: (A1, R, m1, m2, phi) from theta, or None if theta is not an ellipse."""
    t1, t2, t3, t4, t5 = theta
    den = 4 * t1 * t2 - t3 * t3
    if t1 <= 0 or t2 <= 0 or den <= 0:
        return None
    m1 = (2 * t2 * t4 - t5 * t3) / (t3 * t3 - 4 * t1 * t2)
    m2 = (2 * t1 * t5 - t4 * t3) / (t3 * t3 - 4 * t1 * t2)
    a1sq = 4 * t2 * (1 + t1 * m1 ** 2 + t2 * m2 ** 2 + t3 * m1 * m2) / den
    if a1sq <= 0:
        return None
    return np.sqrt(a1sq), np.sqrt(t2 / t1), m1, m2, np.arcsin(t3 / np.sqrt(4 * t1 * t2))


def correct(u1, u2, p):
    """Eq. 9."""
    a1, r, m1, m2, phi = p
    return (u1 - m1) / a1, ((u1 - m1) * np.sin(phi) + r * (u2 - m2)) / (a1 * np.cos(phi))


class Rls:
    """Eq. 7 in double precision, with the gateware's regressor: its third element is
    2 u1 u2 (so the estimate's third element is theta3 / 2; `theta` returns the paper's
    theta), and its trace bound: while the trace of P is above its value after a reset
    (5 kappa), the step does not forget (lambda = 1)."""

    def __init__(self, lambda_k=8, kappa=64.0, theta0=(4.0, 4.0, 0.0, 0.0, 0.0)):
        self.lam = 1.0 / (1.0 + 2.0 ** -lambda_k)
        self.kappa = kappa
        self.th = np.array(theta0, dtype=float) * [1, 1, 0.5, 1, 1]
        self.P = kappa * np.eye(5)

    @property
    def theta(self):
        return self.th * [1, 1, 2, 1, 1]

    def scale_theta(self, dg):
        """The input gain changes by 2**dg: theta follows (exact shifts in the gateware)."""
        self.th[:3] *= 2.0 ** (-2 * dg)
        self.th[3:] *= 2.0 ** (-dg)

    def reset(self):
        self.P = self.kappa * np.eye(5)

    def update(self, x1, x2):
        lam = 1.0 if np.trace(self.P) >= 5 * self.kappa else self.lam
        phi = np.array([x1 * x1, x2 * x2, 2 * x1 * x2, x1, x2])
        h = self.P @ phi
        k = h / (lam + phi @ h)
        self.th = self.th + k * (1.0 - phi @ self.th)
        P = (self.P - np.outer(k, h)) / lam
        # symmetric by construction (the gateware updates one triangle): with forgetting,
        # rounding's antisymmetric part grows as lambda**-t and makes P indefinite after
        # some thousands of updates, even in double precision
        self.P = (P + P.T) / 2
        return self.theta


def run(u1, u2, interp=100, lambda_k=8, kappa=64.0, update_idx=None, period=4096):
    """u1, u2 in full-scale units (codes / 32768). Returns per-sample angle (rad,
    unwrapped), count (x4 of the n-th order) and the parameters in force."""
    n = len(u1)
    rls = Rls(lambda_k, kappa, theta0=(4.0, 4.0, 0.0, 0.0, 0.0))
    p = (0.5, 1.0, 0.0, 0.0, 0.0)
    idx = range(n) if update_idx is None else update_idx
    mask = np.zeros(n, bool)
    mask[list(idx)] = True
    params = np.zeros((n, 5))
    ups = 0
    for k in range(n):
        if mask[k]:
            q = extract(rls.update(u1[k], u2[k]))
            ups += 1
            if q is not None:
                p = q
            if period and ups % period == 0:
                rls.reset()
        params[k] = p
    c1, c2 = correct(u1, u2, params.T)
    ang = np.unwrap(np.arctan2(c2, c1))
    count = np.floor(ang * interp * 2 / np.pi).astype(np.int64)
    return dict(angle=ang, count=count, params=params)


def run_schedule(u1_code, u2_code, sched, interp=100, lambda_k=8, kappa=64.0, adc_w=16,
                 g0=0):
    """The float twin of the gateware: the same estimator schedule as a bit-true model
    run (core.run(...)["sched"]: which samples update, where P is reset and the input
    gain changes, which updates are handed over and from which sample on), in double
    precision, with atan2 and an ideal x4 count of the n-th order. The difference to the
    gateware is then only its word lengths, tables and rounding."""
    u1 = np.asarray(u1_code, float) / (1 << (adc_w - 1))
    u2 = np.asarray(u2_code, float) / (1 << (adc_w - 1))
    n = len(u1)
    rls = Rls(lambda_k, kappa, theta0=(4.0, 4.0, 0.0, 0.0, 0.0))
    g = g0
    cur = (0.5 / 2 ** g, 1.0, 0.0, 0.0, 0.0)   # the default bundle, in input units
    starts, values = [0], [cur]
    for kind, k, g_k, first in sched:
        if kind == "reset":
            rls.scale_theta(g_k - g)
            rls.reset()
            g = g_k
            continue
        rls.update(u1[k] * 2 ** g, u2[k] * 2 ** g)
        if first is not None:
            q = extract(rls.theta)
            if q is not None:
                a1, r, m1, m2, phi = q
                s = 2.0 ** -g
                starts.append(first)
                values.append((a1 * s, r, m1 * s, m2 * s, phi))
    idx = np.searchsorted(np.asarray(starts), np.arange(n), side="right") - 1
    params = np.asarray(values)[idx]
    c1, c2 = correct(u1, u2, params.T)
    ang = np.unwrap(np.arctan2(c2, c1))
    count = np.floor(ang * interp * 2 / np.pi).astype(np.int64)
    return dict(angle=ang, count=count, params=params)
