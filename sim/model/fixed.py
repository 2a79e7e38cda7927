"""Fixed-point primitives shared by every bit-true model function.

The RTL mirrors these exactly (rtl/ modules cite the function they mirror):

* ``sat(v, w)``      -- clamp a Python int to a signed w-bit range.
* ``rnd_shr(v, s)``  -- arithmetic shift right by s with round-half-up
                        (add 2**(s-1) first), computed without overflow.
* ``wrap(v, w)``     -- two's-complement wrap to w bits.
"""


def sat(v: int, w: int) -> int:
    hi = (1 << (w - 1)) - 1
    lo = -(1 << (w - 1))
    return hi if v > hi else lo if v < lo else v


def is_sat(v: int, w: int) -> bool:
    return v > (1 << (w - 1)) - 1 or v < -(1 << (w - 1))


def rnd_shr(v: int, s: int) -> int:
    if s <= 0:
        return v
    return (v + (1 << (s - 1))) >> s


def wrap(v: int, w: int) -> int:
    v &= (1 << w) - 1
    return v - (1 << w) if v >> (w - 1) else v


def clz32(v: int) -> int:
    """Leading zeros of a 32-bit word (v taken as unsigned 32-bit)."""
    v &= 0xFFFFFFFF
    return 32 - v.bit_length()
