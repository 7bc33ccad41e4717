#!/usr/bin/env python3
"""Beam-theory (LEFM) reference curves for the delamination examples.

Formulas: ../../shared/BENCHMARKS.md section 4 (corrected beam theory for
the DCB, Carlsson's ENF compliance and propagation load, Reeder & Crews'
mixed-mode bending split). Writes, next to this script:

  dcb_beam_theory.csv   opening delta (mm), load P on one arm (N)
  enf_beam_theory.csv   mid-span deflection (mm), total load P (N)
  enf_snapback_beam_theory.csv   the same for a0 = 0.5 L (snaps back)

and prints the characteristic numbers. Run: python3 beam_theory.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# AS4/PEEK (Camanho, Davila & de Moura 2003; Camanho & Davila 2002)
E11, E22, G13 = 122700.0, 10100.0, 5500.0
GIC, GIIC, ETA = 0.969, 1.719, 2.284


def chi(e11=E11, e22=E22, g13=G13):
    gamma = 1.18 * math.sqrt(e11 * e22) / g13
    return math.sqrt(e11 / (11.0 * g13) * (3.0 - 2.0 * (gamma / (1.0 + gamma)) ** 2))


def dcb(a0=32.9, b=25.4, h=1.56, corrected=True, delta_max=10.0, n=200):
    """Linear branch delta = 2 P a_e^3 / (3 E I) up to P_c = sqrt(G b E I) / a_e,
    then P = (G b)^(3/4) (E I)^(1/4) sqrt(2 / (3 delta))."""
    ei = E11 * b * h ** 3 / 12.0
    ae = a0 + (chi() * h if corrected else 0.0)
    pc = math.sqrt(GIC * b * ei) / ae
    dc = 2.0 * pc * ae ** 3 / (3.0 * ei)
    pts = [(dc * i / 20.0, pc * i / 20.0) for i in range(21)]
    for i in range(1, n + 1):
        d = dc + (delta_max - dc) * i / n
        pts.append((d, (GIC * b) ** 0.75 * ei ** 0.25 * math.sqrt(2.0 / (3.0 * d))))
    return pc, dc, pts


def enf(a0, L, b=25.4, h=1.56, n=200):
    """C(a) = (3 a^3 + 2 L^3) / (8 E b h^3); P_c(a) = 4 b sqrt(E h^3 G_IIc) / (3 a)."""
    comp = lambda a: (3.0 * a ** 3 + 2.0 * L ** 3) / (8.0 * E11 * b * h ** 3)
    pcrit = lambda a: 4.0 * b * math.sqrt(E11 * h ** 3 * GIIC) / (3.0 * a)
    pc = pcrit(a0)
    pts = [(pc * comp(a0) * i / 20.0, pc * i / 20.0) for i in range(21)]
    for i in range(1, n + 1):
        a = a0 + (L - a0) * i / n
        p = pcrit(a)
        pts.append((p * comp(a), p))
    return pc, pc * comp(a0), pts


def mmb_critical_load(ratio, a0, L, b=25.4, h=1.56):
    """Lever length c giving G_II/G_T = ratio, and the critical load from
    G_I + G_II = G_c(B) with BK (simple beam theory)."""
    # G_II/G_I = 3 (c+L)^2 / (4 (3c-L)^2) = ratio / (1 - ratio)
    q = math.sqrt(4.0 * ratio / (3.0 * (1.0 - ratio)))  # (c+L)/(3c-L)
    c = L * (1.0 + q) / (3.0 * q - 1.0)
    gc = GIC + (GIIC - GIC) * ratio ** ETA
    k = a0 ** 2 / (b ** 2 * h ** 3 * L ** 2 * E11)
    g_per_p2 = k * (0.75 * (3 * c - L) ** 2 + 9.0 / 16.0 * (c + L) ** 2)
    return c, math.sqrt(gc / g_per_p2)


def write(name, pts, header):
    with open(os.path.join(HERE, name), "w") as f:
        f.write(f"# {header}; written by beam_theory.py\n")
        for x, y in pts:
            f.write(f"{x:.6e},{y:.6e}\n")


if __name__ == "__main__":
    pc, dc, pts = dcb()
    write("dcb_beam_theory.csv", pts, "DCB corrected beam theory: opening delta (mm), load P (N)")
    print(f"DCB CBT: peak {pc:.2f} N at delta {dc:.3f} mm; chi = {chi():.4f}")
    for d in (8.0, 10.0):
        print(f"  propagation P({d}) = {(GIC*25.4)**0.75*(E11*25.4*1.56**3/12)**0.25*math.sqrt(2/(3*d)):.2f} N")
    pc, dc, pts = enf(a0=37.5, L=50.0)
    write("enf_beam_theory.csv", pts, "ENF beam theory (a0 = 37.5, L = 50): load-point deflection (mm), load P (N)")
    print(f"ENF: peak {pc:.1f} N at deflection {dc:.3f} mm; at a = L: {pts[-1][1]:.1f} N at {pts[-1][0]:.3f} mm")
    pc, dc, pts = enf(a0=25.0, L=50.0)
    write("enf_snapback_beam_theory.csv", pts, "ENF beam theory (a0 = 25 = 0.5 L, L = 50), crack from a0 to L: load-point deflection (mm), load P (N)")
    dmin = min(x for x, _ in pts[21:])
    print(f"ENF a0 = 0.5 L: peak {pc:.1f} N at deflection {dc:.3f} mm; snaps back to {dmin:.3f} mm; at a = L: {pts[-1][1]:.1f} N at {pts[-1][0]:.3f} mm")
    for r in (0.2, 0.5, 0.8):
        c, p = mmb_critical_load(r, a0=32.9, L=51.0)
        print(f"MMB G_II/G_T = {r}: lever c = {c:.3f} mm, critical load {p:.2f} N")
