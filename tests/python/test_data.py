"""The vkvo module on the shared data (ctest python.data, label `data`; skipped with a message without it): the
Python SuperPoint and SuperGlue against the PyTorch golden outputs, with golden/README.md's tolerances, and a
Python VO run on the first pairs of the EuRoC clip against `vkvo run` on the same pairs."""
import json
import subprocess

import numpy as np
import pytest
import vkvo

from conftest import SOURCE_DIR

EUROC_CONFIG = SOURCE_DIR / "config" / "euroc.yaml"
EUROC_CLIP = "datasets/euroc_mh01_subset/MH_01_easy"
VO_FRAMES = 12  # the first 12 pairs, run three times over: few, since SuperPoint is slow on lavapipe (docs/testing.md)


def sample_descriptor(dense, x, y):
    """SuperPoint's descriptor at pixel (x, y): grid_sample(align_corners=True) of the dense descriptors
    (D x Hc x Wc) at the normalised position, then L2 norm (tests/superpoint/superpoint_reference.hpp)."""
    _, hc, wc = dense.shape
    h, w = hc * 8, wc * 8
    px = ((x - 4 + 0.5) / (w - 4 - 0.5)) * (wc - 1)
    py = ((y - 4 + 0.5) / (h - 4 - 0.5)) * (hc - 1)
    x0, y0 = int(np.floor(px)), int(np.floor(py))
    tx, ty = px - x0, py - y0

    def tap(yy, xx):
        inside = 0 <= xx < wc and 0 <= yy < hc
        return dense[:, yy, xx].astype(np.float64) if inside else np.zeros(len(dense))

    v = (tap(y0, x0) * (1 - tx) + tap(y0, x0 + 1) * tx) * (1 - ty) + \
        (tap(y0 + 1, x0) * (1 - tx) + tap(y0 + 1, x0 + 1) * tx) * ty
    return v / max(np.linalg.norm(v), 1e-12)


def cosine(a, b):
    return float(np.dot(a, b) / np.sqrt(max(np.dot(a, a) * np.dot(b, b), 1e-30)))


@pytest.fixture(scope="module")
def superpoint(shared_data):
    # The ONNX file itself: converted once into $VKVO_CACHE_DIR, as `vkvo run` converts it.
    return vkvo.SuperPoint(shared_data("models/superpoint_v1.onnx"))


@pytest.mark.parametrize("case", ["euroc_0000_crop", "euroc_0005_crop", "euroc_0000", "euroc_0005", "kitti01_0000"])
def test_superpoint_reproduces_the_golden_outputs(shared_data, superpoint, case):
    """golden/README.md: dense scores max abs error <= 2e-3, dense descriptors cosine >= 0.999 per cell, >= 95 % of
    the reference keypoints found within 1 px, descriptor cosine >= 0.995 for those (each compared with the
    reference's dense descriptors sampled where the keypoint was found, as the C++ golden test does)."""
    golden = shared_data(f"golden/superpoint/{case}")
    assert superpoint.precision in ("fp32", "fp16s")  # "auto" never picks fp16, which has wider tolerances
    image = vkvo.imread(golden / "image.png")
    keypoints, scores, descriptors, dense_scores, dense_descriptors = superpoint.detect(image, dense=True)
    ref_dense_scores = np.load(golden / "dense_scores.npy")
    ref_dense_descriptors = np.load(golden / "dense_descriptors.npy")
    ref_keypoints = np.load(golden / "keypoints.npy")
    ref_descriptors = np.load(golden / "descriptors.npy")

    assert dense_scores.shape == ref_dense_scores.shape
    assert np.abs(dense_scores - ref_dense_scores).max() <= 2e-3
    assert dense_descriptors.shape == ref_dense_descriptors.shape
    cell_cosines = (dense_descriptors * ref_dense_descriptors).sum(axis=0) / (
        np.linalg.norm(dense_descriptors, axis=0) * np.linalg.norm(ref_dense_descriptors, axis=0))
    assert cell_cosines.min() >= 0.999

    assert len(keypoints) == len(ref_keypoints)
    distances = np.linalg.norm(ref_keypoints[:, None, :] - keypoints[None, :, :], axis=2)
    nearest = distances.argmin(axis=1)
    found = distances[np.arange(len(ref_keypoints)), nearest] <= 1.0
    assert found.mean() >= 0.95, f"{found.sum()} of {len(ref_keypoints)} reference keypoints within 1 px"
    for i in np.flatnonzero(found):
        j = nearest[i]
        x, y = keypoints[j]
        if (keypoints[j] == ref_keypoints[i]).all():
            assert cosine(sample_descriptor(ref_dense_descriptors, x, y), ref_descriptors[i]) >= 0.99999, \
                "the numpy sampler differs from PyTorch's"
        assert cosine(sample_descriptor(ref_dense_descriptors, x, y), descriptors[j]) >= 0.995


@pytest.fixture(scope="module")
def superglue(shared_data):
    return vkvo.SuperGlue(shared_data("models/superglue_synthetic.onnx"))


@pytest.mark.parametrize("case, image_size", [("euroc_small_unequal", (160, 120)), ("euroc_0000_0005", (752, 480))])
def test_superglue_reproduces_the_golden_outputs(shared_data, superglue, case, image_size):
    """golden/README.md: log-assignment max abs error <= 1e-3 (fp32) / 0.05 (16-bit), >= 97 % identical matches0."""
    golden = shared_data(f"golden/superglue_synthetic/{case}")
    assert json.loads((golden / "params.json").read_text())["image_width"] == image_size[0]
    features = [tuple(np.load(golden / f"{name}{i}.npy") for name in ("keypoints", "scores", "descriptors"))
                for i in (0, 1)]
    matches, scores, log_assignment = superglue.match(features[0], features[1], image_size, dense=True)
    tolerance = 1e-3 if superglue.precision == "fp32" else 0.05
    assert np.abs(log_assignment - np.load(golden / "log_assignment.npy")).max() <= tolerance
    ref_matches = np.load(golden / "matches0.npy")
    assert (matches == ref_matches).mean() >= 0.97


def rotation_from_quaternion(qx, qy, qz, qw):
    return np.array([[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                     [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                     [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])


def test_vo_run_gives_the_cli_trajectory(shared_data, cli, tmp_path):
    """vkvo.run on the first pairs of the clip writes the trajectory and keyframes `vkvo run` writes for the same
    pairs, to the last digit. The pose-at-a-time Odometry tracks each of those pairs to the poses of `vkvo run`'s
    file, to its 9 decimals. (Where a pair becomes a keyframe, the threaded run may match the next pair against
    the keyframe before it while Odometry, one pair at a time, matches it against the new one; on these pairs
    the first is the only keyframe, and the two agree to the digit: docs/accuracy.md.)"""
    clip = shared_data(EUROC_CLIP)
    shared_data("models/superpoint_v1.onnx")  # found by the model search, as `vkvo run` finds it
    subprocess.run([cli, "run", "--config", str(EUROC_CONFIG), "--dataset", str(clip), "--out", str(tmp_path / "cli"),
                    "--last", str(VO_FRAMES - 1)], check=True, capture_output=True)
    result = vkvo.run(EUROC_CONFIG, clip, tmp_path / "python", last=VO_FRAMES - 1, progress=False)
    assert result["frames"] == VO_FRAMES and result["frames_tracked"] == VO_FRAMES
    assert result["trajectory"] == tmp_path / "python" / "trajectory.txt"
    cli_trajectory = (tmp_path / "cli" / "trajectory.txt").read_text()
    assert (tmp_path / "python" / "trajectory.txt").read_text() == cli_trajectory
    assert (tmp_path / "python" / "keyframes.txt").read_text() == (tmp_path / "cli" / "keyframes.txt").read_text()

    dataset = vkvo.Dataset(clip, config=EUROC_CONFIG, last=VO_FRAMES - 1)
    odometry = vkvo.Odometry(EUROC_CONFIG, dataset)
    reference = np.loadtxt(tmp_path / "cli" / "trajectory.txt", ndmin=2)
    assert len(dataset) == len(reference) == VO_FRAMES
    for i, (left, right, t) in enumerate(dataset):
        pose, status = odometry.track(left, right, t)
        assert status["tracked"] and status["new_segment"] == (i == 0), status
        assert t * 1e-9 == pytest.approx(reference[i, 0], abs=1e-6)
        np.testing.assert_allclose(pose[:3, 3], reference[i, 1:4], rtol=0, atol=1e-9)
        np.testing.assert_allclose(pose[:3, :3], rotation_from_quaternion(*reference[i, 4:8]), rtol=0, atol=1e-8)
    assert odometry.tracking_losses == 0
    # Against the ground truth: bound 3 cm, as the C++ test on the first 15 pairs (measured: docs/accuracy.md).
    assert vkvo.evaluate(result["trajectory"], dataset.groundtruth)["ate_translation_m"]["rmse"] < 0.03
