"""Look-up tables of the interpolator and the estimator (Table 1 of the paper, seeds).

One generator serves the RTL ($readmemh files written by scripts/gen_tables.py) and the
bit-true model, so the two can never hold different contents.

Phase units: one signal period is PH_PERIOD = 2**PH_W = 8192 units (u13). One octant is
1024 units; the phase table maps the octant-local address j (u11, 2048 rows) to the
octant-local phase. What j means depends on the table kind (rtl/octant.v):
    - "exact": j = round(2048 |small| / |large|), the tangent of the octant-local angle
      in steps of 1/2048 (both corrected signals are used, so the angle noise is the
      Cramer-Rao bound sigma/A at every angle)
    - "paper": j = round(2048 |small|), the small corrected signal in steps of 1/2048 of
      the unit radius (Table 2, Eq. 10)

* ``phase_table(kind)``: 2048 entries, PHT_W = 12 bits unsigned.
    - "exact": round(atan(j/2048) * 8192 / (2 pi))   (row 2048 would be 1024, one octant)
    - "paper": round(j / (2048 sin(pi/4)) * 1024)      (uniform angle per row, Table 2)
* ``phase_table_4k()``: the exact table in 4096 rows per sign, addressed by the octant's
  sign neg and the scale t of the ratio product (rtl/octant.v t_o = min(4095,
  floor(p / 2**15)), j = (t + 1) >> 1 clipped at 2047): row t holds PH[min(2047,
  (t + 1) >> 1)] and row 4096 + t its complement ~PH (12 bits), so the address needs no
  rounding add and the phase sum no inversion (rtl/lut.v OPT_PHASE_4K, for fast devices:
  8192 rows).
* ``recip_table()``: 512 entries, RCP_W = 14 bits unsigned (u0.14, 8196 .. 16368): the
  reciprocal of the normalised large magnitude m = |large| << z / 2**14 in [1, 2), for the
  bin i = floor((m - 1) * 512) the value that minimises the largest relative error over the
  bin, 2 / (m_lo + m_hi) = 1024 / (1024 + i + 1/2), rounded: round(2**24 / (1025 + 2 i)).
* ``sine_table(sin_w)``: quarter wave, 2048 entries, u0.(SIN_W-1) magnitudes (SIN_W-bit words)
    T[k] = round((2**(SIN_W-1) - 1) * sin((k + 0.5) * (pi/2) / 2048)).
  The half-step offset makes the quarter wave symmetric (index ~k for the mirror).
* ``eq12_k_table(sin_w)``: the Eq. 12 thresholds on the sine table's address side
  (rtl/pulse.v OPT_ADDR), 2**(SIN_W-1) entries (SIN_W 8, 10, 12), 12 bits: row E holds
  K[E] = #{k : T[k] < E} (0 .. 2048), so that T[k] >= E <=> k >= K[E] (T is
  non-decreasing), and T[k] = 0 <=> k < K[1].
* ``bin_thresholds(kind)``: the harmonic table's bin of a sample, phase >> 7 (64 bins of
  128 units), found from the octant address j before the phase table is read: with
  ph = PH[j] and base = 2048 oct2, (base + ph) >> 7 = 16 oct2 + floor(ph / 128) and
  ((base - ph) mod 8192) >> 7 = 16 oct2 - ceil(ph / 128) (mod 64), where
  floor(ph / 128) = #{k : j >= L_k} and ceil(ph / 128) = #{k : j >= U_k} for the first
  j with ph >= 128 k (L_k) and ph > 128 (k - 1) (U_k), k = 1..HBIN_N; 2048 where no row
  reaches it (PH is non-decreasing in j). ``bin_buckets`` arranges them for the RTL.
* ``seed_recip()`` / ``seed_isqrt()``: 128-entry seeds of the engine's reciprocal and
  inverse square root, u1.15 (the engine places them in s2.30 as seed << 15).
"""
import math

PH_W = 13                 # phase index width: u13, 8192 units per signal period
PH_PERIOD = 1 << PH_W
OCT = PH_PERIOD // 8      # 1024 units per octant
ADDR_W = 11               # octant-local address width (2048 rows)
ROWS = 1 << ADDR_W
PHT_W = 12                # phase table word: 0 .. 2048 (u12)
SINE_ROWS = PH_PERIOD // 4  # quarter wave: 2048 rows
KINDS = ("exact", "paper")
RCP_AW = 9                # reciprocal table address: 9 bits of the mantissa below its leading 1
RCP_W = 14                # reciprocal table word: u0.14, always in [2**13, 2**14)


def phase_table(kind: str = "exact") -> list[int]:
    if kind == "exact":
        return [round(math.atan(j / ROWS) * PH_PERIOD / (2 * math.pi)) for j in range(ROWS)]
    if kind == "paper":
        return [round(j / (ROWS * math.sin(math.pi / 4)) * OCT) for j in range(ROWS)]
    raise ValueError(f"table kind must be one of {KINDS}, got {kind!r}")


def phase_table_4k() -> list[int]:
    ph = phase_table("exact")
    rows = [ph[min(ROWS - 1, (t + 1) >> 1)] for t in range(2 * ROWS)]
    return rows + [~v & ((1 << PHT_W) - 1) for v in rows]


def recip_table() -> list[int]:
    """u0.14 reciprocals of the bins of m in [1, 2) (see the module docstring); exact
    integer rounding (half up) of 2**24 / (1025 + 2 i)."""
    return [((1 << 25) + (1025 + 2 * i)) // (2 * (1025 + 2 * i)) for i in range(1 << RCP_AW)]


def sine_table(sin_w: int) -> list[int]:
    amp = (1 << (sin_w - 1)) - 1
    return [round(amp * math.sin((k + 0.5) * (math.pi / 2) / SINE_ROWS))
            for k in range(SINE_ROWS)]


EQ12_K_W = 12             # Eq. 12 threshold word: 0 .. 2048 (u12)
EQ12_K_SIN_W = (8, 10, 12)  # sine widths with a threshold table (2**(SIN_W-1) rows)


def eq12_k_table(sin_w: int) -> list[int]:
    if sin_w not in EQ12_K_SIN_W:
        raise ValueError(f"eq12_k_table: SIN_W must be one of {EQ12_K_SIN_W}, got {sin_w}")
    t = sine_table(sin_w)
    if any(b < a for a, b in zip(t, t[1:])):
        raise ValueError(f"sine_table({sin_w}) is not non-decreasing")
    return [sum(1 for v in t if v < e) for e in range(1 << (sin_w - 1))]


HBIN_N = 12               # thresholds per set: the paper table's PH reaches 1447 < 12 * 128


def bin_thresholds(kind: str = "exact") -> tuple[list[int], list[int]]:
    ph = phase_table(kind)

    def first(pred):
        return next((j for j in range(ROWS) if pred(ph[j])), ROWS)

    lo = [first(lambda v, k=k: v >= 128 * k) for k in range(1, HBIN_N + 1)]
    hi = [first(lambda v, k=k: v > 128 * (k - 1)) for k in range(1, HBIN_N + 1)]
    assert all(ph[j] <= ph[j + 1] for j in range(ROWS - 1))
    assert max(ph) < 128 * HBIN_N
    return lo, hi


def bin_buckets(thresholds: list[int]) -> list[tuple[int, int]]:
    """The thresholds as rtl/octant.v looks them up, on the scale t = floor(p / 2**15)
    of its ratio product p (exact table: j = round(p / 2**16) = (t + 1) >> 1, t = 4095
    when j clips at 2047; paper table: t = 2 j), on which j >= T <=> t >= 2 T - 1. For
    each of the 16 buckets of 256 (t >> 8): (count of thresholds at or below its first
    t, the one threshold inside it minus the first t, or 256 for none), so that
    #{k : j >= T_k} = count + ((t & 255) >= inside). Thresholds that no row reaches
    (T >= ROWS) are left out; the rest are more than 128 rows apart, so a bucket holds at
    most one."""
    tt = [2 * t - 1 for t in thresholds if t < ROWS]
    assert all(b - a > 256 for a, b in zip(tt, tt[1:]))
    out = []
    for b in range(16):
        lo = b << 8
        inside = [t - lo for t in tt if lo < t < lo + 256]
        out.append((sum(t <= lo for t in tt), inside[0] if inside else 256))
    return out


SEED_AW = 7               # seed tables: 128 entries each (one block RAM for both)


def seed_recip() -> list[int]:
    """u1.15 seeds of 1/m; index i = bits [29:23] of m in [2**30, 2**31) (s2.30), the bin
    m in [1 + i/128, 1 + (i+1)/128): the value that minimises the largest relative error
    over the bin, 2 / (m_lo + m_hi)."""
    return [round((1 << 15) * 2 / (2 + (2 * i + 1) / 128)) for i in range(1 << SEED_AW)]


def seed_isqrt() -> list[int]:
    """u1.15 seeds of 1/sqrt(m); index i = bits [30:24] of m in [2**29, 2**31) (s3.29, m in
    [1, 4)), the bin m in [i/32, (i+1)/32) (i >= 32): 1/sqrt at the bin's centre
    (entries below 32 are never used)."""
    return [round((1 << 15) / math.sqrt((max(i, 32) + 0.5) / 32)) for i in range(1 << SEED_AW)]


def hexlines(values, width: int) -> str:
    digits = (width + 3) // 4
    mask = (1 << width) - 1
    return "".join(f"{v & mask:0{digits}x}\n" for v in values)
