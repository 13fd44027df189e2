#!/usr/bin/env python3
"""Writes the seed corpora of the file-reader harnesses (tests/fuzz/corpus/<harness>/seed_*) from the
project's own example files and small inputs made here in the documented formats (docs/fuzzing.md).
Inputs that hold several files use the harnesses' "%%FILE name" sections (fuzz_support.h). Rerun
after a format changes; the LCM seeds come from a log instead (seeds_from_log.py)."""
import json
import math
import os
import pathlib
import struct

ROOT = pathlib.Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "fuzz" / "corpus"


def text(path):
    return (ROOT / path).read_text()


def files(*sections):
    """The first section is the harness's own file; the others are "%%FILE name" sections."""
    out = sections[0][1]
    for name, body in sections[1:]:
        out += f"\n%%FILE {name}\n{body}"  # the line break before a marker is not the file's
    return out


def seed(harness, name, data, prefix=b""):
    d = CORPUS / harness
    d.mkdir(parents=True, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    (d / f"seed_{name}").write_bytes(prefix + data)


def small_obj():
    return "v 0 0 0\nv 0.2 0 0\nv 0.2 0.1 0\nv 0 0.1 0\nvt 0 0\nvt 0.2 0\nvt 0.2 0.1\nvt 0 0.1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"


def ply_ascii():
    return ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n0.2 0 0\n0.2 0.1 0\n0 0.1 0\n3 0 1 2\n3 0 2 3\n")


def ply_binary(endian):
    fmt = "<" if endian == "little" else ">"
    head = (f"ply\nformat binary_{endian}_endian 1.0\nelement vertex 4\nproperty double x\n"
            "property double y\nproperty double z\nproperty float u\nproperty float v\n"
            "element face 2\nproperty list uchar uint vertex_indices\nend_header\n").encode()
    body = b""
    for x, y in [(0, 0), (0.2, 0), (0.2, 0.1), (0, 0.1)]:
        body += struct.pack(fmt + "dddff", x, y, 0.0, x, y)
    for f in [(0, 1, 2), (0, 2, 3)]:
        body += struct.pack(fmt + "BIII", 3, *f)
    return head + body


def small_trial(markers="grid"):
    trial = {
        "material": "composite",
        "sheet": {"width_m": 0.3, "height_m": 0.2},
        "thickness_m": 0.0003,
        "surface_density_kg_m2": 0.3,
        "markers": {"grid": {"rows": 2, "cols": 2, "spacing_m": [0.2, 0.1], "origin_m": [0.05, 0.05]}},
        "clamps": [{"id": "A", "material_point_m": [0.05, 0.18], "grip_radius_m": 0.02},
                   {"id": "B", "material_point_m": [0.25, 0.18], "grip_radius_m": 0.02}],
        "stages": [{"id": "1", "time_s": 0.0, "clamps": {"A": [0.05, 0.0, 1.0], "B": [0.25, 0.0, 1.0]},
                    "markers_file": "1.xyz"},
                   {"id": "2", "time_s": 5.0, "clamps_moved_at_s": 1.0,
                    "clamps": {"A": [0.05, 0.0, 1.0], "B": "released"}, "cloud_file": "2_cloud.xyz"}],
    }
    sections = [("trial.json", json.dumps(trial, indent=1) + "\n"),
                ("1.xyz", "0.05 0.0 0.87\n0.25 0.0 0.87\n0.05 0.0 0.97\nnan nan nan\n"),
                ("2_cloud.xyz", "0.05 0.0 0.9\n0.06 0.0 0.8\n0.05 0.01 0.7\n")]
    if markers == "mesh":
        trial["sheet"] = {"mesh_file": "sheet.obj"}
        trial["markers"] = {"list_m": [[0.05, 0.05], [0.15, 0.05], [0.05, 0.08], [0.15, 0.08]]}
        trial["clamps"][0]["material_point_m"] = [0.02, 0.09]
        trial["clamps"][1]["material_point_m"] = [0.18, 0.09]
        trial["stages"][0]["clamps"] = {"A": [0.02, 0.0, 1.0], "B": [0.18, 0.0, 1.0]}
        trial["stages"][1]["cloud_file"] = "2_cloud.ply"
        sections = [("trial.json", json.dumps(trial, indent=1) + "\n"), sections[1],
                    ("sheet.obj", small_obj()), ("2_cloud.ply", ply_ascii())]
    return files(*sections)


def pgm16(w, h, values):
    return f"P5\n{w} {h}\n65535\n".encode() + b"".join(struct.pack(">H", v) for v in values)


def ppm8(w, h):
    return f"P6\n{w} {h}\n255\n".encode() + bytes((i * 37) % 256 for i in range(w * h * 3))


def session(color):
    w, h = 4, 3
    cam = {"name": "cam", "index": "cam/index.txt", "depth_mode": {"width": w, "height": h, "fps": 30},
           "color_mode": {"width": w if color else 0, "height": h if color else 0, "fps": 30},
           "depth_unit_mm": 1.0,
           "depth_intrinsics": {"width": w, "height": h, "fx": 3.0, "fy": 3.0, "cx": 2.0, "cy": 1.5,
                                "k1": 0, "k2": 0, "p1": 0, "p2": 0, "k3": 0},
           "color_intrinsics": {"width": w if color else 0, "height": h if color else 0, "fx": 3.0,
                                "fy": 3.0, "cx": 2.0, "cy": 1.5, "k1": 0, "k2": 0, "p1": 0, "p2": 0,
                                "k3": 0},
           "depth_to_color": [1, 0, 0, 0.015, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
           "camera_to_cell": [1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 1.8, 0, 0, 0, 1]}
    manifest = json.dumps({"format": "prepreg_camera_session", "version": 1, "cameras": [cam]}, indent=1)
    index = "# sequence device_time_us host_time_us depth_file color_file\n"
    sections = []
    for n in range(2):
        depth = f"depth_{n}.pgm"
        colour = f"color_{n}.ppm" if color else "-"
        index += f"{n} {1000 + n * 33333} {5000 + n * 33333} {depth} {colour}\n"
        sections.append((f"cam/{depth}", pgm16(w, h, [900 + i for i in range(w * h)])))
        if color:
            sections.append((f"cam/{colour}", ppm8(w, h)))
    out = manifest.encode() + b"\n%%FILE cam/index.txt\n" + index.encode()
    for name, body in sections:
        out += f"\n%%FILE {name}\n".encode() + body
    return out


def main():
    # Material, plan, configs: the project's examples.
    seed("material", "composite_prepreg", text("twin/materials/composite_prepreg.json"))
    seed("material", "composite_identified", text("cell/examples/composite_identified.json"))
    seed("material", "composite_truth", text("sim_hw/examples/composite_truth.json"))
    seed("grasp_plan", "four_grasp_plan", text("cell/examples/four_grasp_plan.json"))
    seed("camera_config", "d415_v4l2_cell", text("drivers/examples/d415_v4l2_cell.json"))
    seed("camera_config", "fake_cell", text("cell/examples/fake_cell.json"))
    seed("cell_hardware", "fake_cell", text("cell/examples/fake_cell.json"))
    fake = json.loads(text("cell/examples/fake_cell.json"))
    seed("tracker_config", "fake_cell", json.dumps(fake["tracker"], indent=1))
    seed("tracker_config", "full", json.dumps({
        "fusion": {"pixel_stride": 2, "min_depth_m": 0.3, "max_depth_m": 3.0},
        "segmentation": {"box_min_m": [-1, -1, 0.3], "box_max_m": [1, 1, 2],
                         "color": {"enabled": True, "hue_deg": [10, 40], "unknown": "keep"}},
        "resample": {"voxel_m": 0.01, "remove_outliers": True, "outlier_neighbours": 8},
        "registration": {"max_iterations": 20, "initial_gate_m": 0.1},
        "coverage": {"radius_m": 0.02, "min_points": 3},
        "calibration": {"enabled": True, "every_n_cycles": 30},
        "min_sheet_points": 100}, indent=1))
    cell_files = [("four_grasp_plan.json", text("cell/examples/four_grasp_plan.json")),
                  ("composite_identified.json", text("cell/examples/composite_identified.json")),
                  ("four_grasp_experiment.json", text("cell/examples/four_grasp_experiment.json"))]
    seed("cell_config", "fake_cell", files(("cell.json", text("cell/examples/fake_cell.json")), *cell_files))
    seed("cell_config", "v4l2_cell", files(("cell.json", json.dumps(dict(
        fake, cameras=json.loads(text("drivers/examples/d415_v4l2_cell.json"))["cameras"]), indent=1)),
        *cell_files))
    seed("world_config", "fake_world", files(("world.json", text("sim_hw/examples/fake_world.json")),
                                             ("cell.json", text("cell/examples/fake_cell.json")),
                                             ("composite_truth.json", text("sim_hw/examples/composite_truth.json")),
                                             cell_files[0]))
    seed("experiment", "four_grasp", text("cell/examples/four_grasp_experiment.json"), b"\0")
    averaged = {"mean_mm": 10.0, "max_mm": 50.0}
    seed("experiment", "results", json.dumps({"format": "prepreg_cell_experiment", "version": 1, "states": [
        {"name": "four grasps", "prediction_error": averaged, "algorithm1": averaged,
         "twin_vs_truth": averaged, "tracked_vs_truth": averaged, "window_cycles": 30}]}, indent=1), b"\1")
    seed("openni2_sim_config", "two", json.dumps([
        {"name": "cam_left", "backend": "simulated", "uri": "scene.json", "serial": "821312060001",
         "depth_mode": {"width": 848, "height": 480, "fps": 30},
         "color_mode": {"width": 848, "height": 480, "fps": 30},
         "depth_intrinsics": {"width": 848, "height": 480, "fx": 600, "fy": 600, "cx": 424, "cy": 240},
         "camera_to_cell": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
         "read_timeout_ms": 200, "on_demand": True, "replug_after_ms": 500},
        {"name": "cam_right", "backend": "simulated", "uri": "scene.json",
         "depth_mode": {"width": 848, "height": 480, "fps": 30}}], indent=1))
    # Scenes, scenarios, goals with the files they name.
    seed("d415_scene", "table", text("sim_hw/scenes/d415_table_scene.json"))
    seed("d415_scene", "mesh_files", files(("scene.json", json.dumps({
        "meshes": [{"name": "sheet", "file": "sheet.obj", "albedo": [40, 40, 45]},
                   {"name": "cloth", "file": "cloth.ply"}],
        "noise": {"sigma_at_1m_mm": 1.5, "stereo_shadow": True},
        "faults": {"drop_every_nth": 3, "frozen_from_s": 1.0, "frozen_until_s": 2.0, "stale_mode": "lagging"}},
        indent=1)), ("sheet.obj", small_obj()), ("cloth.ply", ply_ascii())))
    seed("scenario", "five_stages", files(("scenario.json", text("twin/scenarios/composite_five_stages.json")
                                           .replace("../materials/", "")),
                                          ("composite_prepreg.json", text("twin/materials/composite_prepreg.json"))))
    seed("scenario", "mesh_sheet", files(("scenario.json", json.dumps({
        "sheet": {"mesh_file": "sheet.obj", "placement": {"origin_m": [0, 0, 1], "rotation_deg": [90, 0, 0]}},
        "material": json.loads(text("twin/materials/composite_prepreg.json")),
        "clamps": [{"id": "A", "material_point_m": [0.02, 0.09], "grip_radius_m": 0.0}],
        "stages": [{"id": "1", "clamps": {"A": [0.02, 0.0, 1.09]}}],
        "solver": {"increment_m": 0.02, "max_iterations": 20}}, indent=1)), ("sheet.obj", small_obj())))
    seed("grasp_goal", "composite", files(("goal.json", text("cell/examples/composite_goal.json")),
                                         cell_files[1]))
    seed("grasp_goal", "mesh_sheet", files(("goal.json", json.dumps(dict(
        json.loads(text("cell/examples/composite_goal.json")), sheet={"mesh_file": "sheet.obj"}), indent=1)),
        cell_files[1], ("sheet.obj", small_obj())))
    # Trials, meshes and point files in the documented formats.
    seed("trial", "grid", small_trial("grid"))
    seed("trial", "mesh", small_trial("mesh"))
    for i, (name, body) in enumerate([("obj", small_obj()), ("ply_ascii", ply_ascii())]):
        seed("mesh", name, body, bytes([i]))
    seed("mesh", "ply_binary_little", ply_binary("little"), b"\1")
    seed("mesh", "ply_binary_big", ply_binary("big"), b"\2")
    seed("xyz", "markers", "# x y z\n0.1 0.2 1.0\nnan nan nan\n-0.1 2e-1 0.95\n", b"\1")
    seed("xyz", "scan", "0.1 0.2 1.0\n0.11 0.2 1.0\n0.1 0.21 1.01\n", b"\2")
    # Batch manifests with their trial directories (a file in each) and start material, and what a
    # rerun reads back: done.json (fingerprint "fuzz", as the harness sets it) and running.json.
    trial_dirs = [("a_train/trial.json", "{}"), ("a_test/trial.json", "{}"), ("b_train/trial.json", "{}")]
    seed("batch_manifest", "two_materials", files(("manifest.json", json.dumps({
        "materials": [{"name": "lot_a", "train": ["a_train"], "test": ["a_test"], "material": "start.json"},
                      {"name": "lot_b", "train": ["b_train", "a_train"], "test": ["a_test"]}],
        "diagnose": {"triangles": 300, "path_triangles": 0, "refits": 3, "effects": "orthotropic_stiffness",
                     "noise_mm": 0.3, "optimizer": "lm", "discretisation_check": False}}, indent=1)),
        *trial_dirs, ("start.json", text("twin/materials/composite_prepreg.json"))))
    row = {"name": "lot_a", "status": "done", "verdict": "effect", "effect": "orthotropic_stiffness",
           "held_out_before_mm": 0.9, "held_out_after_mm": 0.4, "noise_sigma_mm": 0.3, "seconds": 26.0,
           "error": "", "note": ""}
    seed("batch_manifest", "resume", files(("manifest.json", json.dumps({
        "materials": [{"name": "lot_a", "train": ["a_train"], "test": ["a_test"]}]}, indent=1)),
        *trial_dirs[:2], ("lot_a/done.json", json.dumps({"fingerprint": "fuzz", "row": row}, indent=2)),
        ("lot_a/material.json", "{}"),
        ("lot_a/running.json", json.dumps({"rank": 1, "pid": 4242, "host": "cellpc",
                                           "started": "2026-01-01T08:00:00Z"}, indent=2))))
    # Recorded sessions: depth only and with colour (first byte: replay options).
    seed("session", "depth_only", session(False), b"\0")
    seed("session", "color_loop", session(True), b"\3")
    # The V4L2 device: any bytes drive it (FuzzedDataProvider); a few patterns to start from.
    for n, fill in enumerate([0x00, 0x11, 0xff]):
        seed("v4l2_frames", f"pattern_{n}", bytes([fill]) * 512)
    seed("v4l2_frames", "counting", bytes(i % 256 for i in range(2048)))


def keys_of(value, out):
    if isinstance(value, dict):
        for k, v in value.items():
            out.add(k)
            keys_of(v, out)
    elif isinstance(value, list):
        for v in value:
            keys_of(v, out)


def dictionaries():
    """json.dict: JSON's tokens and every key of the JSON seeds; mesh.dict: OBJ and PLY words."""
    keys = set()
    for path in CORPUS.rglob("seed_*"):
        data = path.read_bytes()
        for part in data.split(b"%%FILE "):
            body = part.split(b"\n", 1)[1] if part is not data.split(b"%%FILE ")[0] else part
            for start in (0, 1):  # some harnesses take a first byte of options
                try:
                    keys_of(json.loads(body[start:]), keys)
                    break
                except (ValueError, UnicodeDecodeError):
                    pass
    tokens = ["{", "}", "[", "]", ":", ",", "\"", "true", "false", "null", "-1", "0", "1e308",
              "-1e308", "1e-320", "NaN", "2147483648", "4294967296", "1e9", "\"released\"",
              "%%FILE ", ".json", ".obj", ".ply", ".xyz"]
    lines = [f'"{t}"' if '"' not in t else '"' + t.replace('"', '\\"') + '"' for t in tokens]
    lines += ['"\\x0a%%FILE "']
    lines += [f'"\\"{k}\\""' for k in sorted(keys)]
    (ROOT / "tests/fuzz/dicts/json.dict").write_text("# JSON tokens and the keys of the seeds (make_seeds.py)\n" +
                                                    "\n".join(lines) + "\n")
    mesh = ["v ", "vt ", "vn ", "f ", "/", "//", "-1", "ply", "format ascii 1.0",
            "format binary_little_endian 1.0", "format binary_big_endian 1.0", "element vertex ",
            "element face ", "property float ", "property double ", "property uchar ", "property int ",
            "property list uchar int vertex_indices", "property list uint uint vertex_index",
            "end_header", "x", "y", "z", "u", "v", "s", "t", "texture_u", "nan", "inf", "comment "]
    (ROOT / "tests/fuzz/dicts/mesh.dict").write_text("# OBJ and PLY words (make_seeds.py)\n" +
                                                    "\n".join(f'"{m}"' for m in mesh) + "\n")


if __name__ == "__main__":
    main()
    dictionaries()
