"""The `vkvo` CLI's contract with scripts (docs/bad-input.md): diagnostics on stderr naming the file, the key and
the problem; exit code 1 for bad input, 2 for a run that produced nothing usable, 3 for an output that could not be
written, 128+N after a signal with the outputs written. No shared data: a rendered sequence and random weights."""
import json
import pathlib
import signal
import subprocess
import time

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
EUROC_CONFIG = SOURCE_DIR / "config" / "euroc.yaml"


def vkvo_cli(cli, *args):
    return subprocess.run([cli, *map(str, args)], capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def sequence(cli, tmp_path_factory):
    """A 4-frame 320x240 rendered EuRoC-layout sequence."""
    out = tmp_path_factory.mktemp("cli") / "sequence"
    subprocess.run([cli, "synth", "--out", str(out), "--preset", "small", "--frames", "4"], check=True,
                   capture_output=True)
    return out


def run_args(sequence, out, random_packs, config=EUROC_CONFIG):
    return ["run", "--config", config, "--dataset", sequence, "--out", out, "--model",
            random_packs / "random_superpoint.vkvopack"]


def poses_in(trajectory):
    return [line for line in trajectory.read_text().splitlines() if line and not line.startswith("#")]


def config_with(key, value, path):
    """config/euroc.yaml with one (indented) key's value replaced, written to `path`; returns its 0-based line."""
    lines = EUROC_CONFIG.read_text().splitlines()
    index = next(i for i, line in enumerate(lines) if line.strip().startswith(f"{key}:"))
    lines[index] = f"  {key}: {value}"
    path.write_text("\n".join(lines) + "\n")
    return index


def test_a_config_value_out_of_range_names_file_key_and_line(cli, sequence, random_packs, tmp_path):
    config = tmp_path / "bad.yaml"
    index = config_with("max_depth", -5, config)
    result = vkvo_cli(cli, *run_args(sequence, tmp_path / "out", random_packs, config))
    assert result.returncode == 1
    assert f"bad.yaml: stereo.max_depth (line {index + 1}): -5 is outside" in result.stderr
    assert "error" not in result.stdout  # results on stdout, diagnostics on stderr
    assert not (tmp_path / "out" / "trajectory.txt").exists()  # refused before any work


def test_a_run_whose_every_frame_is_skipped_exits_2(cli, sequence, random_packs, tmp_path):
    # Right images of another size than the calibration: every frame is skipped, nothing is usable.
    mismatched = tmp_path / "mismatched"
    subprocess.run([cli, "synth", "--out", str(mismatched), "--preset", "small", "--frames", "4", "--resolution",
                    "160", "120"], check=True, capture_output=True)
    for image in (sequence / "mav0" / "cam0" / "data").iterdir():
        (mismatched / "mav0" / "cam0" / "data" / image.name).write_bytes(image.read_bytes())
    out = tmp_path / "out"
    result = vkvo_cli(cli, *run_args(mismatched, out, random_packs))
    assert result.returncode == 2, result.stderr
    assert "image is 320x240 but the calibration says 160x120" in result.stderr
    assert "no frame could be used" in result.stderr
    assert "ATE" not in result.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["frames_skipped"] == 4
    assert summary["frames_tracked"] == 0
    assert poses_in(out / "trajectory.txt") == []


def test_a_benchmark_whose_every_run_tracks_nothing_exits_2(cli, sequence, random_packs, tmp_path):
    # No frame can start a map: each run is reported failed in the table (not as an ATE of 0), and the benchmark
    # as a whole produced nothing usable.
    config = tmp_path / "unreachable.yaml"
    config_with("init_min_keypoints", 1000000, config)
    out = tmp_path / "out"
    result = vkvo_cli(cli, "robustness", "--config", config, "--dataset", sequence, "--out", out, "--model",
                      random_packs / "random_superpoint.vkvopack", "--matcher", "nn", "--scenarios", "clean",
                      "--ablate-lines")
    assert result.returncode == 2, result.stderr
    assert "| clean | failed: no frame tracked |" in (out / "robustness.md").read_text()
    runs = json.loads((out / "robustness.json").read_text())
    assert [(run["lines"], run["error"], run["frames_untracked"]) for run in runs] == [
        (True, "no frame tracked", 4), (False, "no frame tracked", 4)]


def test_sigterm_writes_the_outputs_and_exits_143(cli, random_packs, tmp_path):
    sequence = tmp_path / "long"
    subprocess.run([cli, "synth", "--out", str(sequence), "--preset", "small", "--frames", "100"], check=True,
                   capture_output=True)
    out = tmp_path / "out"
    process = subprocess.Popen([cli, *map(str, run_args(sequence, out, random_packs))], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    trajectory = out / "trajectory.txt"
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and process.poll() is None:
        if trajectory.exists() and len(poses_in(trajectory)) >= 3:
            break
        time.sleep(0.1)
    assert process.poll() is None, "the run ended before it could be stopped"
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=300)
    assert process.returncode == 128 + signal.SIGTERM, stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stopped_early"] is True
    assert summary["frames_in_dataset"] == 100
    assert 3 <= summary["frames"] < 100
    assert len(poses_in(trajectory)) == summary["frames"]  # every processed frame kept its pose
    assert (out / "map.ply").stat().st_size > 0


def test_an_output_folder_that_cannot_be_created_exits_3(cli, sequence, random_packs, tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder\n")
    result = vkvo_cli(cli, *run_args(sequence, blocker / "out", random_packs))
    assert result.returncode == 3, result.stderr
    assert f"output folder {blocker / 'out'}: cannot create it" in result.stderr


def test_an_npy_shape_whose_byte_count_overflows_is_refused(cli, tmp_path):
    features = {}
    for name in ("a", "b"):
        folder = tmp_path / name
        folder.mkdir()
        rng = np.random.default_rng(len(name))
        np.save(folder / "keypoints.npy", rng.uniform(0, 100, (8, 2)).astype(np.float32))
        np.save(folder / "scores.npy", rng.uniform(0, 1, 8).astype(np.float32))
        np.save(folder / "descriptors.npy", rng.normal(size=(8, 256)).astype(np.float32))
        features[name] = folder
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (4611686018427387904, 256), }"
    header = header.ljust(117) + "\n"
    (features["b"] / "descriptors.npy").write_bytes(b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") +
                                                     header.encode() + bytes(64))
    result = vkvo_cli(cli, "match", "--model", "nn", "--features0", features["a"], "--features1", features["b"],
                      "--image-size", "320x240", "--out", tmp_path / "matches")
    assert result.returncode == 1, result.stderr
    assert "descriptors.npy: shape (4611686018427387904, 256) overflows the byte count" in result.stderr


def test_synth_refuses_a_zero_resolution(cli, tmp_path):
    result = vkvo_cli(cli, "synth", "--out", tmp_path / "s", "--preset", "small", "--frames", "2", "--resolution",
                      "0", "10")
    assert result.returncode == 1
    assert "resolution 0x10 is outside 16x16" in result.stderr
