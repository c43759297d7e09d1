#!/usr/bin/env python3
"""Derives the range-reduction constants of the fast sin and cos (shared/articula/platform.h,
detail::sincos_kernel) from first principles, and checks the values written there.

pi comes from Machin's formula, pi/4 = 4 atan(1/5) - atan(1/239), summed with Python
integers as a 400-bit fixed-point number (each arctan series is truncated term by term with
20 guard bits; the result is good to far better than 2^-380). Everything after that is exact
rational arithmetic (fractions.Fraction):

    P1 = pi/2 rounded to 37 significant bits   (|k| < 2^16, so k*P1 is exact in a double)
    P2 = (pi/2 - P1) rounded to 37 bits        (k*P2 exact too)
    P3 = (pi/2 - P1 - P2) rounded to 53 bits   (a full double)

and 2/pi is rounded to the nearest double. The polynomial coefficients need no derivation:
they are +-1/n!, written as quotients in the header and rounded once by the compiler.

Usage: python3 bench/sincos_constants.py [path/to/platform.h]   (exit code 1 on a mismatch)
"""
import os
import re
import sys
from fractions import Fraction

BITS = 400
GUARD = 20


def arctan_inverse(n: int) -> int:
    """arctan(1/n) * 2^BITS by its Taylor series 1/n - 1/(3 n^3) + ..., in integers."""
    one = 1 << (BITS + GUARD)
    power = one // n  # 2^(BITS+GUARD) / n^(2k+1)
    total = power
    n2 = n * n
    k = 1
    while power:
        power //= n2
        term = power // (2 * k + 1)
        total += -term if k % 2 else term
        k += 1
    return total >> GUARD


def pi_fraction() -> Fraction:
    return Fraction(4 * (4 * arctan_inverse(5) - arctan_inverse(239)), 1 << BITS)


def round_to_bits(x: Fraction, bits: int) -> Fraction:
    """x rounded to the nearest number with `bits` significant bits (ties: even)."""
    if x == 0:
        return x
    e = 0
    a = abs(x)
    while a >= 2:
        a /= 2
        e += 1
    while a < 1:
        a *= 2
        e -= 1
    scale = Fraction(2) ** (bits - 1 - e)
    return Fraction(round(x * scale)) / scale


def main() -> int:
    pi = pi_fraction()
    digits = str(pi.numerator * 10**50 // pi.denominator)
    assert digits.startswith("314159265358979323846264338327950288419716939937510"), digits
    half = pi / 2
    p1 = round_to_bits(half, 37)
    p2 = round_to_bits(half - p1, 37)
    p3 = round_to_bits(half - p1 - p2, 53)
    two_over_pi = float(2 / pi)  # float() rounds a Fraction to the nearest double
    derived = {"2/pi": two_over_pi, "P1": float(p1), "P2": float(p2), "P3": float(p3)}
    for name, value in (("P1", p1), ("P2", p2), ("P3", p3)):
        assert Fraction(float(value)) == value, name  # each is exactly a double
    print(f"pi = 3.{digits[1:]}...")
    for name, value in derived.items():
        print(f"{name:5s} = {value!r:26s} {value.hex()}")
    residual = half - p1 - p2 - p3
    print(f"pi/2 - (P1 + P2 + P3) = {float(residual):.3e}")

    header = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "shared", "articula", "platform.h")
    text = open(header, encoding="utf-8").read()
    block = text[text.index("#define ARTICULA_SINCOS_CONSTANTS"):]
    written = [float(v) for v in re.findall(r"X\(([-0-9.e]+)\)", block)[:5]]
    names = ["2/pi", "shift", "P1", "P2", "P3"]
    ok = True
    for name, value in zip(names, written):
        expected = 6755399441055744.0 if name == "shift" else derived[name]
        if value != expected:
            print(f"MISMATCH {name}: header {value!r}, derived {expected!r}")
            ok = False
    print("platform.h agrees" if ok else "platform.h disagrees")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
