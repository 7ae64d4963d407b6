#!/usr/bin/env python3
"""Writes the broken seeds of fuzz/corpus/sweep_json/ as edits of ok-cmcsurf.json (the
sweep.json of `cmcsurf sweep --surface G --volume-fractions 0.5 --grid 16 --epsilon 0.04
--max-steps 2 --no-plot --no-preview --no-report`). Not part of any build; from the repository
root: python3 fuzz/make_sweep_json_seeds.py"""
import copy
import json
import os

DIR = "fuzz/corpus/sweep_json"
with open(os.path.join(DIR, "ok-cmcsurf.json")) as f:
    OK = json.load(f)


def put(name, edit):
    s = copy.deepcopy(OK)
    edit(s)
    with open(os.path.join(DIR, name), "w") as f:
        json.dump(s, f, indent=2)


def setter(*path_and_value):
    *path, key, value = path_and_value

    def edit(s):
        for p in path:
            s = s[p]
        s[key] = value
    return edit


put("ok-two-surfaces-continuation.json", lambda s: s.update(
    surfaces=["G", "expr:cos(x)+cos(y)+cos(z)"], volume_fractions=[0.3, 0.5], members=4,
    continuation=True))
put("bad-max-steps-wraps.json", setter("parameters", "max_steps", 4294967298))
put("bad-grid-fraction.json", setter("parameters", "grid", 16.5))
put("bad-seed-negative.json", setter("parameters", "seed", -1))
put("bad-member-escapes.json", setter("surfaces", ["../victim/G"]))
put("bad-surface-not-string.json", setter("surfaces", [7]))
put("bad-fraction-range.json", setter("volume_fractions", [0.5, 1.5]))
put("bad-fraction-string.json", setter("volume_fractions", ["0.5"]))
put("bad-continuation-string.json", setter("continuation", "yes"))
put("bad-members-over.json", setter("members", 2))
put("bad-threads-top.json", setter("threads", -1))
put("bad-outputs-threads-wraps.json", setter("outputs", "threads", 4294967298))
put("bad-outputs-every.json", setter("outputs", "checkpoint_every", -1))
put("bad-outputs-flag.json", setter("outputs", "float32", 1))
put("bad-outputs-python.json", setter("outputs", "python", ["/bin/sh"]))
put("bad-outputs-not-object.json", setter("outputs", 3))
put("bad-no-parameters.json", lambda s: s.pop("parameters"))
put("bad-mpi-ranks.json", setter("mpi", {"ranks": 0, "groups": 1, "ranks_per_group": 1}))
with open(os.path.join(DIR, "bad-not-json.json"), "w") as f:
    f.write('{"surfaces": ["G"], ')
with open(os.path.join(DIR, "bad-empty.json"), "w") as f:
    pass
with open(os.path.join(DIR, "bad-array.json"), "w") as f:
    f.write("[1, 2, 3]\n")
