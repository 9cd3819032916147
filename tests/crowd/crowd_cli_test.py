#!/usr/bin/env python3
"""End-to-end checks of cc_crowd's command line, scene files and outputs (registered in CTest by
tests/crowd/CMakeLists.txt).

    crowd_cli_test.py run CC_CROWD OUT_DIR          a short rendered run: exit 0, summary.json fields finite
    crowd_cli_test.py reject PATTERN CC_CROWD ARGS  exits non-zero, stderr matches PATTERN
    crowd_cli_test.py roundtrip CC_CROWD OUT_DIR    --write-scene output reads back as the same scene and crowd
    crowd_cli_test.py export CC_CROWD OUT_DIR       --export obj and glb write every character's body and garment
    crowd_cli_test.py churn CC_CROWD OUT_DIR        --churn replaces characters mid-run; frames.csv logs memory
    crowd_cli_test.py tradeoff CC_CROWD OUT_DIR     --tradeoff's windowed errors rank: the reference's own
                                                    refinement nearest, more level, substeps, iterations nearer
"""
import csv
import json
import math
import os
import re
import struct
import subprocess
import sys


def run(argv):
    return subprocess.run(argv, capture_output=True, text=True, timeout=120)


def check(condition, message):
    if not condition:
        sys.exit("FAIL: " + message)


def short_run(exe, out, *extra):
    p = run([exe, "--characters", "12", "--seconds", "1", "--width", "320", "--height", "180", "--out", out, *extra])
    check(p.returncode == 0, f"exit code {p.returncode}\nstdout:\n{p.stdout}\nstderr:\n{p.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def finite(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def test_run(exe, out):
    s = short_run(exe, out, "--no-video", "--frame-stats", "--color-by", "lod")
    for key in ["characters", "frames", "threads", "budgetMs", "failedUpdates", "renderedFrames", "wallSeconds",
                "meanGarmentsUpdated", "meanGarmentsVisible", "meanGarmentsAsleep"]:
        check(finite(s.get(key)), f"summary.json '{key}' is {s.get(key)!r}, not a finite number")
    for key in ["median", "p99", "max"]:
        check(finite(s["frameMs"].get(key)) and s["frameMs"][key] > 0, f"frameMs.{key} is {s['frameMs'].get(key)!r}")
    levels = s["meanGarmentsPerLevel"]
    check(len(levels) == 8 and all(finite(x) for x in levels), f"meanGarmentsPerLevel {levels}")
    check(abs(sum(levels) - 12) < 1e-9, f"mean garments per level sum to {sum(levels)}, not 12")
    check(s["characters"] == 12 and s["frames"] == 60 and s["renderedFrames"] == 15, f"counts in {s}")
    check(s["video"] is None, "--no-video wrote a video")
    pngs = [n for n in os.listdir(os.path.join(out, "frames")) if n.startswith("frame_") and n.endswith(".png")]
    check(len(pngs) == 15, f"{len(pngs)} PNG frames, not 15")
    with open(os.path.join(out, "frames.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == 60, f"frames.csv has {len(rows)} rows, not 60")
    check(all(math.isfinite(float(v)) for r in rows for v in r.values()), "frames.csv has a non-finite value")
    with open(os.path.join(out, "frame_stats.jsonl")) as f:
        lines = [json.loads(line) for line in f]
    check(len(lines) == 60, f"frame_stats.jsonl has {len(lines)} lines, not 60")


def test_churn(exe, out):
    # 12 characters, twice replaced each second: 24 leave and join during the second.
    s = short_run(exe, out, "--no-render", "--churn", "2")
    check(s["failedUpdates"] == 0, f"{s['failedUpdates']} failed updates with churn")
    with open(os.path.join(out, "frames.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == 60, f"frames.csv has {len(rows)} rows, not 60")
    for key in ["residentMb", "heapMb"]:
        check(all(float(r[key]) > 0 for r in rows), f"frames.csv '{key}' is not positive in every row")


def test_reject(pattern, exe, args):
    p = run([exe, *args])
    check(p.returncode != 0, f"{args} exited 0")
    check(re.search(pattern, p.stderr), f"{args}: stderr does not match {pattern!r}:\n{p.stderr}")


def test_roundtrip(exe, out):
    os.makedirs(out, exist_ok=True)
    first, second = os.path.join(out, "scene.json"), os.path.join(out, "scene-again.json")
    p = run([exe, "--characters", "12", "--write-scene", first])
    check(p.returncode == 0, f"--write-scene: {p.stderr}")
    p = run([exe, "--scene", first, "--write-scene", second])
    check(p.returncode == 0, f"--scene {first} --write-scene: {p.stderr}")
    with open(first) as a, open(second) as b:
        check(json.load(a) == json.load(b), "the scene read back and written again differs from the one written")
    overridden = os.path.join(out, "scene-overridden.json")
    p = run([exe, "--scene", first, "--seconds", "2.5", "--write-scene", overridden])
    check(p.returncode == 0, f"--scene {first} --seconds 2.5 --write-scene: {p.stderr}")
    with open(overridden) as f:
        check(json.load(f)["seconds"] == 2.5, "--seconds does not override the scene file's")
    built_in = short_run(exe, os.path.join(out, "built-in"), "--no-render")
    from_file = short_run(exe, os.path.join(out, "from-file"), "--no-render", "--scene", first)
    for key in ["characters", "frames", "budgetMs", "seconds"]:
        check(built_in[key] == from_file[key], f"'{key}': {built_in[key]} built in, {from_file[key]} from the file")


def test_export(exe, out):
    characters, frames = 3, 2  # 30 frames rendered every 15th
    for fmt in ["obj", "glb"]:
        p = run([exe, "--characters", str(characters), "--seconds", "0.5", "--render-every", "15", "--width", "64",
                 "--height", "64", "--no-video", "--export", fmt, "--out", os.path.join(out, fmt)])
        check(p.returncode == 0, f"--export {fmt}: exit code {p.returncode}\n{p.stderr}")
        directory = os.path.join(out, fmt, "export")
        files = sorted(n for n in os.listdir(directory) if n.endswith("." + fmt))
        check(files == [f"frame_{i:05d}.{fmt}" for i in range(1, frames + 1)], f"--export {fmt} wrote {files}")
        with open(os.path.join(directory, files[-1]), "rb") as f:
            data = f.read()
        if fmt == "obj":
            names = re.findall(rb"^o (\w+)$", data, re.M)
            faces = len(re.findall(rb"^f ", data, re.M))
        else:
            check(data[:4] == b"glTF", "the .glb does not start with the glTF magic")
            length, = struct.unpack("<I", data[12:16])
            gltf = json.loads(data[20:20 + length])
            names = [n["name"].encode() for n in gltf["nodes"] if "mesh" in n]
            faces = sum(gltf["accessors"][prim["indices"]]["count"] // 3 for m in gltf["meshes"] for prim in m["primitives"])
        expected = sorted([f"body_{i}".encode() for i in range(characters)] + [f"garment_{i}".encode() for i in range(characters)])
        check(sorted(names) == expected, f"--export {fmt} meshes {names}")
        check(faces > 0, f"--export {fmt} has no triangles")


def test_tradeoff(exe, out):
    p = run([exe, "--tradeoff", "--seconds", "1", "--out", out])
    check(p.returncode == 0, f"--tradeoff exit code {p.returncode}\nstdout:\n{p.stdout}\nstderr:\n{p.stderr}")
    with open(os.path.join(out, "tradeoff.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    scenes = {r["scene"] for r in rows}
    check(scenes == {"cape/walk", "cape/run", "skirt/walk"}, f"scenes {scenes}")
    check(all(r["ok"] == "1" and finite(float(r["rms_mm"])) and finite(float(r["ms"])) for r in rows), "a failed row")
    check(os.path.getsize(os.path.join(out, "tradeoff.png")) > 10000, "no tradeoff.png")

    def rms(scene, knob, **key):
        match = [r for r in rows if r["scene"] == scene and r["knob"] == knob and all(r[k] == str(v) for k, v in key.items())]
        check(len(match) == 1, f"{scene} {knob} {key}: {len(match)} rows")
        return float(match[0]["rms_mm"])

    check(re.search(r"^BAR presets front=[01] scenes=3 presets=3$", p.stdout, re.M), "no BAR presets line")
    for scene in scenes:
        check(any(r["front"] == "1" for r in rows if r["scene"] == scene), f"{scene}: no front")
        # Every preset is measured in every scene, ordered: Fast no finer than Balanced, no finer than Quality.
        level = {}
        for r in rows:
            for name in filter(None, r["preset"].split("+")):
                if r["scene"] == scene:
                    level[name] = int(r["level"])
        check(set(level) == {"fast", "balanced", "quality"}, f"{scene}: presets {sorted(level)}")
        check(level["fast"] <= level["balanced"] <= level["quality"], f"{scene}: preset levels {level}")
        # The reference checked by one more refinement in time lies nearer than any shipped level:
        # the error it measures is the configurations', not the reference's own.
        reference = rms(scene, "ref-time")
        for level in range(5):
            check(reference < rms(scene, "level", level=level), f"{scene}: ref-time {reference} mm not below level {level}")
    # Convergence the windows can see on the skirt (smooth contact with the hips and legs): the
    # finest level against the coarsest, many substeps or iterations against one.
    check(rms("skirt/walk", "level", level=4) < 0.8 * rms("skirt/walk", "level", level=0), "skirt: level 4 not nearer than 0")
    check(rms("skirt/walk", "substeps", substeps=32) < 0.6 * rms("skirt/walk", "substeps", substeps=1), "skirt: substeps")
    check(rms("skirt/walk", "iterations", iterations=16) < 0.6 * rms("skirt/walk", "iterations", iterations=1),
          "skirt: iterations")


def main():
    command, args = sys.argv[1], sys.argv[2:]
    if command == "run":
        test_run(*args)
    elif command == "reject":
        test_reject(args[0], args[1], args[2:])
    elif command == "roundtrip":
        test_roundtrip(*args)
    elif command == "export":
        test_export(*args)
    elif command == "churn":
        test_churn(*args)
    elif command == "tradeoff":
        test_tradeoff(*args)
    else:
        sys.exit(f"unknown command {command!r}")


if __name__ == "__main__":
    main()
