#!/usr/bin/env python3
"""Writes seed inputs for FuzzWorld.cpp that build a working crowd (assets, bodies, characters,
garments, steps), so that the fuzzer starts from inputs that reach the solver. The encoding
mirrors FuzzWorld.cpp's Input reader; rerun after changing it: python3 make_seeds.py corpus/"""
import random
import struct
import sys


class Seed:
    def __init__(self):
        self.out = bytearray()

    def b(self, v):
        self.out.append(v & 0xFF)

    def u32(self, v):
        self.out += struct.pack('>I', v & 0xFFFFFFFF)

    def real(self, fraction):  # a plausible value: fraction of the reader's [lo, hi]
        self.b(8)
        self.u32(int(fraction * 4294967295))

    def awkward(self, kind):  # 0 NaN, 1 inf, 2 -inf, 3 zero, 4 -1, 5 1e300, 6 -hi
        self.b(kind)


def world(s, rng):
    s.b(rng.randrange(2))   # threads
    for _ in range(4):
        s.b(1)              # keep the world defaults


def asset(s, rng, kind):
    s.b(0)
    s.b(kind); s.b(rng.randrange(3)); s.b(2); s.b(0)    # kind, cut, 3 levels, render level 2
    for _ in range(3):
        s.b(0)                                          # width, length, hem fitted
    for _ in range(5):
        s.b(1)                                          # defaults


def mannequin(s, rng):
    s.b(1)
    s.real(rng.uniform(0.3, 0.7)); s.real(rng.uniform(0.3, 0.7)); s.real(rng.uniform(0.3, 0.7))


def character(s, rng, clip):
    s.b(3)
    s.b(0)                  # body 0
    s.b(clip)
    s.real(0.1); s.real(0.1); s.real(0.5); s.real(0.5)


def steps(s, count):
    s.b(9); s.b(count - 1)
    for _ in range(count):
        s.b(1)


def make(rng, variant):
    s = Seed()
    world(s, rng)
    mannequin(s, rng)
    kinds = [variant % 4, (variant + 1) % 4]
    for k in kinds:
        asset(s, rng, k)
    for c in range(3):
        character(s, rng, rng.randrange(3))
    for c in range(3):
        # pick(): byte % count; assets 0..1, characters 0..2
        s.b(4); s.real(0.5); s.b(1); s.real(0.5); s.b(c % 2); s.b(c)
    steps(s, 4)
    s.b(5); s.real(0.6); s.real(0.5); s.real(0.6); s.real(0.5); s.b(1)   # move a character
    if variant % 3 == 0:
        s.b(5); s.awkward(0); s.real(0.5); s.real(0.5); s.real(0.5); s.b(0)  # a NaN root
    if variant % 3 == 1:
        s.b(9); s.b(0); s.b(0); s.awkward(variant % 7)                      # an awkward dt
    steps(s, 4)
    return bytes(s.out)


if __name__ == '__main__':
    out = sys.argv[1] if len(sys.argv) > 1 else 'corpus'
    rng = random.Random(11)
    for v in range(12):
        with open(f'{out}/crowd-{v:02d}', 'wb') as f:
            f.write(make(rng, v))
