"""The compiled ``bilinear`` traction law written again in Python (numpy), to
register with ``junta.register_law`` -- an example of a Python law, and the
reference the tests hold the Python-law machinery to (the same curve as the
compiled law to 1e-9).

It follows ``crates/interface/src/law/cohesive.rs`` and ``bilinear.rs``
operation by operation: mixed-mode bilinear softening (Camanho & Davila
2002, Turon et al. 2006) with one penalty ``K`` (``shear_penalty =
"equal"``), the quadratic onset criterion with the positive part of the
normal traction, Benzeggagh-Kenane propagation ``G_c = G_Ic + (G_IIc -
G_Ic) B^eta``, damage as the history variable, exact dissipated energy,
penalty contact, optional viscous regularisation, and the tangent as the
exact derivative of the branch taken (forward-mode dual numbers, vectorised
over the points: :class:`Dual`).

State per point (as the compiled law): ``[damage history, damage used by
the traction, fracture energy, viscous energy, mode ratio, onset index]``.

Units are the scene's (the DCB examples: N, mm, MPa; energies N/mm).

>>> import junta, bilinear_law
>>> bilinear_law.register()            # as "py_bilinear"
>>> # in a scene: [laws.cz] type = "py_bilinear"  K = 1e6  N = 80 ...
"""

import math

import numpy as np

#: Damage above which a damage value is taken as exactly 1 (cohesive.rs `FULL`).
FULL = 1.0 - 1e-12
DAMAGE_HISTORY, DAMAGE, ENERGY, VISCOUS, MODE_RATIO, INDEX = range(6)
STATE_LEN = 6


def _pow(x, p):
    """``x ** p`` element by element through the C library's ``pow`` (as
    Rust's ``f64::powf``): numpy's own SIMD ``power`` can differ in the last
    bit, and this law is meant to agree with the compiled one to the bit."""

    def one(v):
        try:
            return math.pow(v, p)
        except (ValueError, OverflowError):
            return math.nan

    return np.fromiter((one(v) for v in x.tolist()), dtype=float, count=len(x))


class Dual:
    """Values ``v [n]`` with gradients ``d [n, 3]`` in the three jump
    components: junta_core's ``Dual3``, one per point, with the same
    formulas (so that values and tangents agree to round-off)."""

    __slots__ = ("v", "d")

    def __init__(self, v, d=None):
        self.v = np.asarray(v, dtype=float)
        self.d = np.zeros(self.v.shape + (3,)) if d is None else d

    @staticmethod
    def seeds(x):
        n = len(x)
        out = []
        for i in range(3):
            d = np.zeros((n, 3))
            d[:, i] = 1.0
            out.append(Dual(x[:, i].copy(), d))
        return out

    @staticmethod
    def cst(v, n):
        return Dual(np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy())

    def _chain(self, v, dv):
        return Dual(v, self.d * dv[:, None])

    def __add__(self, o):
        if isinstance(o, Dual):
            return Dual(self.v + o.v, self.d + o.d)
        return Dual(self.v + o, self.d)

    __radd__ = __add__

    def __neg__(self):
        return Dual(-self.v, -self.d)

    def __sub__(self, o):
        if isinstance(o, Dual):
            return Dual(self.v - o.v, self.d - o.d)
        return Dual(self.v - o, self.d)

    def __rsub__(self, o):  # f64 - Dual = -o + self
        return (-self) + o

    def __mul__(self, o):
        if isinstance(o, Dual):
            return Dual(self.v * o.v, self.d * o.v[:, None] + self.v[:, None] * o.d)
        return Dual(self.v * o, self.d * o)

    __rmul__ = __mul__

    def __truediv__(self, o):
        if isinstance(o, Dual):
            with np.errstate(divide="ignore", invalid="ignore"):
                inv = 1.0 / o.v
                q = self.v * inv
                return Dual(q, (self.d - q[:, None] * o.d) * inv[:, None])
        return self * (1.0 / o)

    def __rtruediv__(self, o):
        return Dual(np.full_like(self.v, o)) / self

    def sqrt(self):
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.sqrt(self.v)
            dv = np.where(s > 0.0, 0.5 / np.where(s > 0.0, s, 1.0), 0.0)
        return self._chain(s, dv)

    def powf(self, p):
        zero = self.v == 0.0
        with np.errstate(divide="ignore", invalid="ignore"):
            v = _pow(self.v, p)
            dv = p * v / self.v
        v = np.where(zero, 1.0 if p == 0.0 else 0.0, v)
        dv = np.where(zero, 0.0, dv)
        out = self._chain(v, dv)
        out.d[zero] = 0.0
        return out

    def pos(self):
        keep = self.v > 0.0
        return Dual(np.where(keep, self.v, 0.0), np.where(keep[:, None], self.d, 0.0))

    def where(self, mask, other):
        """``self`` where ``mask``, else ``other``."""
        return Dual(np.where(mask, self.v, other.v), np.where(mask[:, None], self.d, other.d))


class PyBilinear:
    """The ``bilinear`` law; parameters as the compiled law: ``K``, ``N``,
    ``S``, ``G_Ic``, ``G_IIc``, ``eta`` (BK), optional ``viscosity``; the
    quadratic onset and ``shear_penalty = "equal"`` only."""

    state_len = STATE_LEN
    tangent_kind = "indefinite"
    output_names = ["damage", "dissipated_energy", "viscous_energy", "mode_ratio"]

    def __init__(self, params):
        known = {"K", "N", "S", "G_Ic", "G_IIc", "eta", "viscosity", "propagation", "onset"}
        unknown = sorted(set(params) - known)
        if unknown:
            raise ValueError(f"unknown parameters {unknown}; valid: {sorted(known)}")
        if params.get("propagation", "bk") != "bk" or params.get("onset", "quadratic") != "quadratic":
            raise ValueError("py_bilinear supports propagation = \"bk\" and onset = \"quadratic\" only")
        for k in ("K", "N", "S", "G_Ic", "G_IIc", "eta"):
            if k not in params:
                raise ValueError(f"missing `{k}`")
            if not float(params[k]) > 0.0:
                raise ValueError(f"`{k}` = {params[k]} must be positive")
        self.kn = self.ks = float(params["K"])
        self.n = float(params["N"])
        self.s = float(params["S"])
        self.g1 = float(params["G_Ic"])
        self.g2 = float(params["G_IIc"])
        self.eta = float(params["eta"])
        self.viscosity = float(params.get("viscosity", 0.0))
        self.initial_stiffness = (self.ks, self.ks, self.kn)
        self.fracture_properties = {"N": self.n, "S": self.s, "G_Ic": self.g1, "G_IIc": self.g2}

    # -- the pieces of cohesive.rs and bilinear.rs ---------------------------

    def onset_index(self, t0):
        """Quadratic criterion of the undamaged traction (degree 2)."""
        s = t0[2].pos() / self.n
        a = t0[0] / self.s
        b = t0[1] / self.s
        return s * s + a * a + b * b

    def toughness(self, b):
        """BK: ``G_c = B^eta (G_IIc - G_Ic) + G_Ic``."""
        return b.powf(self.eta) * (self.g2 - self.g1) + self.g1

    @staticmethod
    def damage(lam, lam0, g_c, k_b):
        """Linear softening ``d = lam_f (lam - lam0) / (lam (lam_f - lam0))``."""
        n = len(lam.v)
        lam_f = g_c * 2.0 / (k_b * lam0)
        d = (lam_f * (lam - lam0) / (lam * (lam_f - lam0)))
        zero = Dual.cst(0.0, n)
        d = zero.where(zero.v > d.v, d)  # Dual3::max: ties keep self
        return Dual.cst(1.0, n).where(lam.v >= lam_f.v, d)

    @staticmethod
    def dissipated(d, lam0, g_c, k_b):
        """Energy of a monotone path to damage ``d`` (``F(1) = G_c``)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            lam_f = 2.0 * g_c / (k_b * lam0)
            lam = lam_f * lam0 / (lam_f - d * (lam_f - lam0))
            f = g_c * (lam - lam0) / (lam_f - lam0)
        return np.where(d <= 0.0, 0.0, np.where(d >= 1.0, g_c, f))

    def mode_properties(self, b):
        """``(lam0, g_c, k_b)`` at mode ratio ``b`` (values)."""
        n = len(b)
        with np.errstate(invalid="ignore"):
            ds = np.sqrt(b / self.ks)
            dn = np.sqrt((1.0 - b) / self.kn)
        j = Dual.seeds(np.stack([ds, np.zeros(n), dn], axis=1))
        idx = self.onset_index([j[0] * self.ks, j[1] * self.ks, j[2] * self.kn]).v
        k_b = (1.0 - b) * self.kn + b * self.ks
        lam = np.sqrt(1.0 / k_b)
        lam0 = lam * _pow(idx, -1.0 / 2.0)
        g_c = self.toughness(Dual(b)).v
        return lam0, g_c, k_b

    def relax_viscous(self, c, dt, two_psi, trial, mask):
        """Viscous damage relaxing towards the history where ``mask``."""
        dt = max(dt, 0.0)
        mu = self.viscosity
        dv0 = c[:, DAMAGE]
        dv = (mu * dv0 + dt * c[:, DAMAGE_HISTORY]) / (mu + dt)
        up = mask & (dv > dv0)
        if up.any():
            lam0, g_c, k_b = self.mode_properties(c[:, MODE_RATIO])
            frac = self.dissipated(dv, lam0, g_c, k_b) - self.dissipated(dv0, lam0, g_c, k_b)
            trial[:, ENERGY] = np.where(up, c[:, ENERGY] + frac, trial[:, ENERGY])
            trial[:, VISCOUS] = np.where(up, c[:, VISCOUS] + 0.5 * two_psi * (dv - dv0) - frac, trial[:, VISCOUS])
        trial[:, DAMAGE] = np.where(mask, dv, trial[:, DAMAGE])
        return dv

    # -- the law's interface ---------------------------------------------------

    def evaluate(self, jump, state, step):
        n = len(jump)
        c = state
        trial = c.copy()
        ks, kn = self.ks, self.kn
        dj = Dual.seeds(jump)
        dn_pos = dj[2].pos()
        t0 = [dj[0] * ks, dj[1] * ks, dn_pos * kn]
        shear2 = (dj[0] * dj[0] + dj[1] * dj[1]) * ks
        two_psi = shear2 + dn_pos * dn_pos * kn
        d_hist = c[:, DAMAGE_HISTORY]
        d = Dual.cst(d_hist, n)
        loaded = two_psi.v > 0.0
        with np.errstate(divide="ignore", invalid="ignore"):
            b = shear2 / two_psi
            idx = self.onset_index(t0)
            trial[:, MODE_RATIO] = np.where(loaded, b.v, trial[:, MODE_RATIO])
            trial[:, INDEX] = np.where(loaded, idx.v, trial[:, INDEX])
            onset = loaded & (idx.v > 1.0) & (d_hist < 1.0)
            t0_norm = (t0[0] * t0[0] + t0[1] * t0[1] + t0[2] * t0[2]).sqrt()
            lam = two_psi / t0_norm
            lam0 = lam * idx.powf(-1.0 / 2.0)
            k_b = (1.0 - b) * kn + b * ks
            g_c = self.toughness(b)
            d_b = self.damage(lam, lam0, g_c, k_b)
            d_b = Dual.cst(1.0, n).where(d_b.v >= FULL, d_b)
            grow = onset & ((d_b.v > d_hist) | ((d_b.v == d_hist) & (d_hist > 0.0)))
            d = d_b.where(grow, d)
            trial[:, DAMAGE_HISTORY] = np.where(grow, d.v, trial[:, DAMAGE_HISTORY])

            def f(x):
                return self.dissipated(x, lam0.v, g_c.v, k_b.v)

            dt = max(float(step["delta_load_factor"]), 0.0)
            if self.viscosity == 0.0:
                more = onset & (d.v > d_hist)
                trial[:, ENERGY] = np.where(more, c[:, ENERGY] + f(d.v) - f(d_hist), trial[:, ENERGY])
                trial[:, DAMAGE] = np.where(onset, d.v, trial[:, DAMAGE])
            else:
                mu = self.viscosity
                dv0 = c[:, DAMAGE]
                dv = (d * dt + dv0 * mu) / (mu + dt)
                frac = f(dv.v) - f(dv0)
                trial[:, DAMAGE] = np.where(onset, dv.v, trial[:, DAMAGE])
                trial[:, ENERGY] = np.where(onset, c[:, ENERGY] + frac, trial[:, ENERGY])
                trial[:, VISCOUS] = np.where(
                    onset, c[:, VISCOUS] + 0.5 * two_psi.v * (dv.v - dv0) - frac, trial[:, VISCOUS]
                )
                d = dv.where(onset, d)
                # not loading (below onset, or no energy): relax towards the history
                rest = ~onset
                dvr = self.relax_viscous(c, float(step["delta_load_factor"]), np.where(loaded, two_psi.v, 0.0), trial, rest)
                d = Dual(dvr).where(rest, d)
        one_m_d = 1.0 - d
        t = [
            one_m_d * dj[0] * ks,
            one_m_d * dj[1] * ks,
            (one_m_d * dj[2] * kn).where(dj[2].v > 0.0, dj[2] * kn),
        ]
        traction = np.stack([x.v for x in t], axis=1)
        tangent = np.stack([x.d for x in t], axis=1)
        if step.get("secant"):
            s = 1.0 - d.v
            tangent = np.zeros((n, 3, 3))
            tangent[:, 0, 0] = s * ks
            tangent[:, 1, 1] = s * ks
            tangent[:, 2, 2] = np.where(jump[:, 2] > 0.0, s * kn, kn)
        return traction, tangent, trial

    def outputs(self, state):
        return state[:, [DAMAGE, ENERGY, VISCOUS, MODE_RATIO]]

    def failure_index(self, state):
        return state[:, INDEX]


def register(name="py_bilinear"):
    """Register :class:`PyBilinear` with junta under ``name``."""
    import junta

    junta.register_law(
        name,
        PyBilinear,
        description="the compiled `bilinear` law written in Python (numpy dual numbers)",
        params={
            "K": "penalty stiffness (both modes)",
            "N": "normal strength",
            "S": "shear strength",
            "G_Ic": "mode I toughness",
            "G_IIc": "mode II toughness",
            "eta": "BK exponent",
            "viscosity": "viscous regularisation (default 0)",
        },
    )


def main():
    """Register the law and check its tangent against central differences
    at points below onset, softening and past full separation (the DCB's
    parameters, N/mm units)."""
    import junta

    register()
    params = {"K": 1.0e6, "N": 80.0, "S": 100.0, "G_Ic": 0.969, "G_IIc": 1.719, "eta": 2.284}
    jumps = np.array([[0.0, 0.0, 2e-5], [1e-5, 0.0, 1e-4], [2e-4, 1e-4, 5e-3], [0.0, 0.0, 5e-2]])
    r = junta.check_tangent(PyBilinear(params), jumps, h=1e-9, rtol=1e-4)
    print(f"py_bilinear registered; tangent against central differences at {len(jumps)} points: "
          f"max relative error {r['max_rel_error']:.2e} ({'ok' if r['ok'] else 'FAILED'})")
    return 0 if r["ok"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
