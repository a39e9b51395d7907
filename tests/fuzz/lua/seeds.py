#!/usr/bin/env python3
# seeds.py: writes the Lua harness's seed corpus (tests/fuzz/lua/corpus/).
# An input is a program for fuzz_lua.c's generator: each statement is an
# opcode byte (0-33) followed by its operands. The seeds are a few
# hand-written programs (a scene rendered, explained, listed, saved and
# read back; tricks around scene:add and render) and pseudo-random byte
# strings from a fixed seed. Run from the repository's top; a seed must run
# clean (build/fuzz/fuzz_lua FILE), so one that meets a known bug is left
# out by hand. Read one as Lua: FUZZ_LUA_PRINT=1 build/fuzz/fuzz_lua FILE.
import os
import random

OUT = "tests/fuzz/lua/corpus"

SKIP_FIELDS = b"\xff" * 22         # pick(8) = 7: a field left out

# Every statement reads: opcode, slot i, slot j, choice byte c, then its own.


def render(slot, into):
    # op 18: V[into] = K('lancer.Scene', slot):render{}; receiver K, no
    # trick, every option left out, no misspelling
    return bytes([18, slot, into, 0, 0, 0]) + SKIP_FIELDS[:19] + b"\x00"


def whole_scene(slot):
    return bytes([11, slot, 0, 0])   # op 11: a small scene that renders


PROGRAMS = {
    # a scene rendered into V[2], saved as a.png (op 27), read back into V[3]
    "scene_render_save": whole_scene(0) + render(0, 1) +
        bytes([27, 1, 0, 0, 1, 0, 0, 0]) + bytes([27, 2, 0, 0, 0, 0, 0]),
    # explain (op 20) of pixel (1, 1), objects (op 21) listed, one removed
    "explain_objects": whole_scene(0) + bytes([20, 0, 1, 0, 0, 0]) + SKIP_FIELDS +
        b"\x00\x00" + bytes([21, 0, 0, 0, 0, 1, 0, 21, 0, 0, 1, 0, 2, 0]),
    # a host hook (op 30) that collects garbage around plain, then a render
    "hook_render": whole_scene(0) + bytes([30, 0, 0, 3, 1, 3]) + render(0, 1),
    # a translation (op 12), a group of the sphere and the light (op 13)
    # moved by it (op 14), added to the scene (op 16)
    "group_moved": whole_scene(0) + bytes([12, 5, 0, 0, 0, 0, 1, 0, 1, 0, 1]) +
        bytes([13, 6, 0, 0, 2, 0, 3, 0, 6]) +
        bytes([14, 7, 0, 0, 6, 5, 5]) + bytes([16, 0, 0, 0, 0, 0, 0, 7]),
}


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, data in PROGRAMS.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
    rng = random.Random(11)
    for k in range(12):
        n = rng.choice([48, 96, 200, 400, 800])
        with open(os.path.join(OUT, "random_%02d" % k), "wb") as f:
            f.write(bytes(rng.randrange(256) for _ in range(n)))


if __name__ == "__main__":
    main()
