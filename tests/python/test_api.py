"""The vkvo module without shared data (ctest python.api, label `python`): networks with random weights against
numpy references of what they must return, every input layout, and the errors bad input gets."""
import json
import subprocess

import numpy as np
import pytest
import vkvo

from conftest import SOURCE_DIR

EUROC_CONFIG = SOURCE_DIR / "config" / "euroc.yaml"


def textured_image(height, width, seed):
    """Smooth blobs plus noise (uint8), so that the score map has distinct local maxima."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:height, 0:width]
    image = np.zeros((height, width))
    for _ in range(12):
        cy, cx, r = rng.uniform(0, height), rng.uniform(0, width), rng.uniform(3, 10)
        image += rng.uniform(60, 120) * np.exp(-((y - cy) ** 2 + (x - cx) ** 2) / (2 * r * r))
    image += rng.normal(0, 8, image.shape)
    return np.clip(image + 40, 0, 255).astype(np.uint8)


def opencv_grey(bgr):
    """OpenCV's 8-bit BGR -> grey: 0.114 B + 0.587 G + 0.299 R in 15-bit fixed point, rounded."""
    b, g, r = (bgr[..., c].astype(np.int64) for c in range(3))
    return ((b * 3735 + g * 19235 + r * 9798 + (1 << 14)) >> 15).astype(np.uint8)


def unit_rows(rng, n, dim):
    d = rng.normal(size=(n, dim)).astype(np.float32)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def assert_same_features(a, b):
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)


# --- devices -----------------------------------------------------------------------------------------------------

def test_devices_lists_every_device_with_its_precisions():
    devices = vkvo.devices()
    assert devices, "no Vulkan device"
    for index, device in enumerate(devices):
        assert device["index"] == index
        assert device["name"]
        assert device["type"] in ("discrete", "integrated", "virtual", "cpu", "other")
        assert "fp32" in device["precisions"]
        assert device["preferred_precision"] in device["precisions"]


# --- SuperPoint --------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def superpoint(random_packs):
    return vkvo.SuperPoint(random_packs / "random_superpoint.vkvopack", precision="fp32")


def test_superpoint_outputs_agree_with_its_dense_maps(superpoint):
    image = textured_image(96, 120, seed=3)
    keypoints, scores, descriptors, dense_scores, dense_descriptors = superpoint.detect(image, dense=True)
    assert superpoint.precision == "fp32" and superpoint.descriptor_dim == 256
    n = len(keypoints)
    assert 0 < n <= 400
    assert keypoints.dtype == scores.dtype == descriptors.dtype == np.float32
    assert keypoints.shape == (n, 2) and scores.shape == (n,) and descriptors.shape == (n, 256)
    assert dense_scores.shape == (96, 120) and dense_descriptors.shape == (256, 12, 15)
    assert np.all(np.diff(scores) <= 0), "score-descending"
    # Keypoints sit on pixels, inside the 4-pixel border, above the threshold, with the dense map's score, and
    # no two within the NMS radius (4: a 9 x 9 window) of each other.
    x, y = keypoints[:, 0].astype(int), keypoints[:, 1].astype(int)
    np.testing.assert_array_equal(keypoints, np.stack([x, y], axis=1))
    assert x.min() >= 4 and y.min() >= 4 and x.max() < 120 - 4 and y.max() < 96 - 4
    assert scores.min() >= 0.005
    np.testing.assert_array_equal(scores, dense_scores[y, x])
    chebyshev = np.maximum(np.abs(x[:, None] - x[None, :]), np.abs(y[:, None] - y[None, :]))
    assert (chebyshev + 9 * np.eye(n, dtype=int)).min() > 4
    np.testing.assert_allclose(np.linalg.norm(descriptors, axis=1), 1, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(dense_descriptors, axis=0), 1, atol=1e-5)
    # dense=False returns the same keypoints.
    assert_same_features(superpoint.detect(image), (keypoints, scores, descriptors))


def test_superpoint_subpixel_moves_keypoints_to_the_log_score_peak(random_packs, superpoint):
    image = textured_image(96, 120, seed=3)
    whole, scores, descriptors, dense_scores, _ = superpoint.detect(image, dense=True)
    fine = vkvo.SuperPoint(random_packs / "random_superpoint.vkvopack", precision="fp32", subpixel=True)
    keypoints, fine_scores, fine_descriptors = fine.detect(image)
    # Same keypoints, scores and descriptors; each position moved by the vertex of the parabola through the log
    # scores of the pixel and its two neighbours, per axis, at most half a pixel.
    np.testing.assert_array_equal(fine_scores, scores)
    np.testing.assert_array_equal(fine_descriptors, descriptors)
    log = np.log(np.maximum(dense_scores.astype(np.float64), 1e-30))
    x, y = whole[:, 0].astype(int), whole[:, 1].astype(int)

    def vertex(left, centre, right):
        curvature = left - 2 * centre + right
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(curvature < 0, np.clip(0.5 * (left - right) / curvature, -0.5, 0.5), 0.0)

    expected = whole + np.stack([vertex(log[y, x - 1], log[y, x], log[y, x + 1]),
                                 vertex(log[y - 1, x], log[y, x], log[y + 1, x])], axis=1)
    np.testing.assert_allclose(keypoints, expected, atol=1e-4)
    assert np.mean(np.any(keypoints != whole, axis=1)) > 0.5, "most peaks lie between pixels"


def test_superpoint_takes_any_layout_and_bgr(superpoint):
    image = textured_image(64, 80, seed=5)
    expected = superpoint.detect(image)
    assert_same_features(superpoint.detect(np.asfortranarray(image)), expected)
    wide = np.zeros((128, 160), np.uint8)
    wide[::2, ::2] = image
    assert_same_features(superpoint.detect(wide[::2, ::2]), expected)       # strided view
    assert_same_features(superpoint.detect(image[:, :, None]), expected)     # (H, W, 1)
    assert_same_features(superpoint.detect(np.repeat(image[:, :, None], 3, axis=2)), expected)  # grey as BGR
    bgr = np.stack([textured_image(64, 80, seed=s) for s in (6, 7, 8)], axis=2)
    assert_same_features(superpoint.detect(bgr), superpoint.detect(opencv_grey(bgr)))


@pytest.mark.parametrize("image, error, message", [
    (np.zeros((64, 64), np.float32), ValueError, "expected a uint8 image, got dtype float32"),
    (np.zeros((64, 64), np.uint16), ValueError, "expected a uint8 image, got dtype uint16"),
    (np.zeros((64, 64, 4), np.uint8), ValueError, r"expected shape \(H, W\) or \(H, W, 3\) \(BGR\), got \(64, 64, 4\)"),
    (np.zeros(64, np.uint8), ValueError, r"got \(64,\)"),
    (np.zeros((0, 64), np.uint8), ValueError, "the image is empty"),
    (np.zeros((8, 12), np.uint8), ValueError, "image 12x8 is smaller than 16x16"),
    ([[0, 1], [2, 3]], TypeError, "expected a numpy array, got list"),
])
def test_superpoint_rejects_bad_images(superpoint, image, error, message):
    with pytest.raises(error, match=message):
        superpoint.detect(image)


def test_superpoint_rejects_bad_arguments(random_packs, tmp_path):
    missing = tmp_path / "missing.vkvopack"
    with pytest.raises(FileNotFoundError, match=f"superpoint model {missing} does not exist"):
        vkvo.SuperPoint(missing)
    garbage = tmp_path / "garbage.vkvopack"
    garbage.write_bytes(b"not a model pack")
    with pytest.raises(RuntimeError, match="garbage.vkvopack"):
        vkvo.SuperPoint(garbage)
    with pytest.raises(RuntimeError, match="random_superglue.vkvopack"):  # a pack of the other network
        vkvo.SuperPoint(random_packs / "random_superglue.vkvopack")
    with pytest.raises(ValueError, match="precision 'fp64': expected auto, fp32, fp16s or fp16"):
        vkvo.SuperPoint(random_packs / "random_superpoint.vkvopack", precision="fp64")
    with pytest.raises(ValueError, match="keypoint_threshold"):
        vkvo.SuperPoint(random_packs / "random_superpoint.vkvopack", keypoint_threshold=-1)
    with pytest.raises(TypeError, match="device: expected None, an index or a name"):
        vkvo.SuperPoint(random_packs / "random_superpoint.vkvopack", device=1.5)
    with pytest.raises(vkvo.VulkanError, match="no-such-device"):
        vkvo.SuperPoint(random_packs / "random_superpoint.vkvopack", device="no-such-device")


# --- SuperGlue and the nearest-neighbour matcher ----------------------------------------------------------------

def random_features(rng, n, dim, width=640, height=480):
    keypoints = np.stack([rng.uniform(0, width, n), rng.uniform(0, height, n)], axis=1).astype(np.float32)
    return keypoints, rng.uniform(0, 1, n).astype(np.float32), unit_rows(rng, n, dim)


def superglue_extract(log_assignment, threshold):
    """SuperGlue's match extraction: mutual row/column maxima of the inner block, kept above the threshold."""
    inner = log_assignment[:-1, :-1]
    best1, best0 = inner.argmax(axis=1), inner.argmax(axis=0)
    mutual = best0[best1] == np.arange(len(inner))
    scores = np.where(mutual, np.exp(inner.max(axis=1)), 0)
    return np.where(mutual & (scores > threshold), best1, -1), scores


def test_superglue_matches_follow_its_log_assignment(random_packs):
    superglue = vkvo.SuperGlue(random_packs / "random_superglue.vkvopack", precision="fp32")
    rng = np.random.default_rng(11)
    a, b = random_features(rng, 60, 32), random_features(rng, 45, 32)
    # b shares 30 of a's keypoints (shuffled, slightly moved) so that there is something to match.
    shared = rng.permutation(60)[:30]
    b[0][:30], b[2][:30] = a[0][shared] + rng.normal(0, 0.5, (30, 2)), a[2][shared]
    matches, scores, log_assignment = superglue.match(a, b, image_size=(640, 480), dense=True)
    assert matches.dtype == np.int32 and matches.shape == (60,)
    assert scores.dtype == np.float32 and scores.shape == (60,)
    assert log_assignment.shape == (61, 46)
    expected_matches, expected_scores = superglue_extract(log_assignment.astype(np.float64), 0.2)
    np.testing.assert_array_equal(matches, expected_matches)
    np.testing.assert_allclose(scores, expected_scores, rtol=1e-5, atol=1e-7)
    assert (matches >= 0).sum() > 0  # random weights follow the descriptors loosely: 4 of the 30 shared here
    # dense=False returns the same matches; other array layouts the same again.
    np.testing.assert_array_equal(superglue.match(a, b, image_size=(640, 480))[0], matches)
    fortran = tuple(np.asfortranarray(x) for x in a)
    as_float64 = tuple(x.astype(np.float64) for x in b)
    np.testing.assert_array_equal(superglue.match(fortran, as_float64, (640, 480))[0], matches)


def test_superglue_rejects_bad_features(random_packs):
    superglue = vkvo.SuperGlue(random_packs / "random_superglue.vkvopack")
    rng = np.random.default_rng(2)
    a, b = random_features(rng, 10, 32), random_features(rng, 12, 32)
    with pytest.raises(ValueError, match=r"\(width, height\) of the image is needed"):
        superglue.match(a, b)
    with pytest.raises(ValueError, match="expected a positive"):
        superglue.match(a, b, image_size=(0, 480))
    with pytest.raises(ValueError, match=r"features0 keypoints: expected shape \(N, 2\), got \(10, 3\)"):
        superglue.match((np.zeros((10, 3)), a[1], a[2]), b, (640, 480))
    with pytest.raises(ValueError, match=r"features1 scores: expected shape \(12,\)"):
        superglue.match(a, (b[0], b[1][:5], b[2]), (640, 480))
    with pytest.raises(ValueError, match="features0 descriptors: expected real numbers, got dtype <U1"):
        superglue.match((a[0], a[1], np.full((10, 32), "x")), b, (640, 480))
    with pytest.raises(ValueError, match="SuperGlue"):  # 64-d descriptors for a 32-d network
        superglue.match(random_features(rng, 10, 64), random_features(rng, 12, 64), (640, 480))
    with pytest.raises(TypeError, match=r"expected \(keypoints, scores, descriptors\)"):
        superglue.match(a[0], b, (640, 480))


def mutual_nearest_neighbours(d0, d1, max_cosine_distance, ratio):
    similarity = d0.astype(np.float64) @ d1.astype(np.float64).T
    best1, best0 = similarity.argmax(axis=1), similarity.argmax(axis=0)
    best = similarity.max(axis=1)
    keep = (best0[best1] == np.arange(len(d0))) & (1 - best <= max_cosine_distance)
    if ratio > 0:
        second = np.sort(similarity, axis=1)[:, -2]
        keep &= np.sqrt(np.maximum(2 - 2 * best, 0)) < ratio * np.sqrt(np.maximum(2 - 2 * second, 0))
    return np.where(keep, best1, -1), np.where(keep, best, 0)


@pytest.mark.parametrize("ratio", [0.0, 0.9])
def test_nn_matcher_finds_the_mutual_nearest_neighbours(ratio):
    rng = np.random.default_rng(5)
    d0 = unit_rows(rng, 80, 256)
    noisy = d0[rng.permutation(80)[:50]] + rng.normal(0, 0.03, (50, 256)).astype(np.float32)
    d1 = np.concatenate([noisy / np.linalg.norm(noisy, axis=1, keepdims=True), unit_rows(rng, 20, 256)])
    f0 = (np.zeros((80, 2), np.float32), np.ones(80, np.float32), d0)
    f1 = (np.zeros((70, 2), np.float32), np.ones(70, np.float32), d1)
    matches, scores = vkvo.NNMatcher(ratio=ratio).match(f0, f1)
    expected_matches, expected_scores = mutual_nearest_neighbours(d0, d1, 0.245, ratio)
    np.testing.assert_array_equal(matches, expected_matches)
    np.testing.assert_allclose(scores, expected_scores, atol=1e-5)
    assert (matches >= 0).sum() >= 45


def test_nn_matcher_handles_empty_sets_and_rejects_mismatched_descriptors():
    matcher = vkvo.NNMatcher()
    rng = np.random.default_rng(1)
    empty = (np.zeros((0, 2), np.float32), np.zeros(0, np.float32), np.zeros((0, 256), np.float32))
    some = (np.zeros((5, 2), np.float32), np.ones(5, np.float32), unit_rows(rng, 5, 256))
    matches, scores = matcher.match(some, empty)
    np.testing.assert_array_equal(matches, np.full(5, -1))
    assert matcher.match(empty, some)[0].shape == (0,)
    with pytest.raises(ValueError, match="descriptors of 256 and 128 dimensions"):
        matcher.match(some, (some[0], some[1], unit_rows(rng, 5, 128)))


# --- evaluate ----------------------------------------------------------------------------------------------------

def write_tum(path, times, positions, quaternions=None):
    if quaternions is None:
        quaternions = np.tile([0.0, 0.0, 0.0, 1.0], (len(times), 1))
    with open(path, "w") as f:
        for t, p, q in zip(times, positions, quaternions):
            f.write(f"{t:.9f} {p[0]:.9f} {p[1]:.9f} {p[2]:.9f} {q[0]:.9f} {q[1]:.9f} {q[2]:.9f} {q[3]:.9f}\n")


@pytest.fixture
def helix(tmp_path):
    t = np.arange(100) * 0.05
    positions = np.stack([np.cos(t), np.sin(t), 0.2 * t], axis=1)
    groundtruth = tmp_path / "groundtruth.txt"
    write_tum(groundtruth, t, positions)
    return t, positions, groundtruth


def test_evaluate_measures_known_errors(helix, tmp_path, cli):
    t, positions, groundtruth = helix
    offset = np.array([0.3, -0.4, 0.0])  # 0.5 m
    shifted = tmp_path / "shifted.txt"
    write_tum(shifted, t, positions + offset)
    aligned = vkvo.evaluate(shifted, groundtruth)
    assert aligned["poses"]["associated"] == 100
    assert aligned["ate_translation_m"]["rmse"] < 1e-6          # SE3 alignment takes the offset out
    unaligned = vkvo.evaluate(shifted, groundtruth, align="none")
    assert unaligned["ate_translation_m"]["rmse"] == pytest.approx(0.5, abs=1e-6)
    half = tmp_path / "half.txt"
    write_tum(half, t, 0.5 * positions)
    assert vkvo.evaluate(half, groundtruth)["ate_translation_m"]["rmse"] > 0.1
    sim3 = vkvo.evaluate(half, groundtruth, align="sim3")
    assert sim3["ate_translation_m"]["rmse"] < 1e-6 and sim3["alignment"]["scale"] == pytest.approx(2, rel=1e-6)
    # The dict is the document `vkvo eval --json` writes.
    report = tmp_path / "eval.json"
    subprocess.run([cli, "eval", "--estimate", str(shifted), "--groundtruth", str(groundtruth), "--json",
                    str(report)], check=True, capture_output=True)
    assert aligned == json.loads(report.read_text())


def test_evaluate_rejects_bad_input(helix, tmp_path):
    t, positions, groundtruth = helix
    with pytest.raises(FileNotFoundError, match="estimate .*missing.txt does not exist"):
        vkvo.evaluate(tmp_path / "missing.txt", groundtruth)
    with pytest.raises(ValueError, match="align 'affine': expected none, se3 or sim3"):
        vkvo.evaluate(groundtruth, groundtruth, align="affine")
    later = tmp_path / "later.txt"
    write_tum(later, t + 1000, positions)
    with pytest.raises(RuntimeError, match="associate"):
        vkvo.evaluate(later, groundtruth)


# --- Odometry, Dataset and run ---------------------------------------------------------------------------------

# EuRoC's cam0 / cam1 (MH_01_easy sensor.yaml) at half their resolution (a quarter of the network's time), as a
# Kalibr camchain.
CAMCHAIN = """cam0:
  camera_model: pinhole
  intrinsics: [229.327, 228.648, 183.6075, 124.1875]
  distortion_model: radtan
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  resolution: [376, 240]
cam1:
  T_cn_cnm1:
  - [0.999997256477881, 0.002312067192424, 0.000376008102415, -0.110073808127187]
  - [-0.002317135723281, 0.999898048506644, 0.014089835846648, 0.000399121547014]
  - [-0.000343393120525, -0.014090668452714, 0.999900662637729, -0.000853702503357]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  intrinsics: [228.7935, 228.067, 189.9995, 127.619]
  distortion_model: radtan
  distortion_coeffs: [-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05]
  resolution: [376, 240]
"""


@pytest.fixture(scope="module")
def camchain(tmp_path_factory):
    path = tmp_path_factory.mktemp("calibration") / "camchain.yaml"
    path.write_text(CAMCHAIN)
    return path


def test_odometry_tracks_pairs_and_checks_them(random_packs, camchain):
    odometry = vkvo.Odometry(EUROC_CONFIG, camchain, model=random_packs / "random_superpoint.vkvopack",
                             matcher="nn", precision="fp32")
    left, right = textured_image(240, 376, seed=1), textured_image(240, 376, seed=2)
    pose, status = odometry.track(left, right, 1_000_000_000)
    assert pose.shape == (4, 4) and pose.dtype == np.float64
    np.testing.assert_allclose(pose[:3, :3] @ pose[:3, :3].T, np.eye(3), atol=1e-9)
    np.testing.assert_array_equal(pose[3], [0, 0, 0, 1])
    assert status["frame_index"] == 0 and status["timestamp_ns"] == 1_000_000_000
    assert set(status) >= {"tracked", "keyframe", "new_segment", "tracked_points", "tracked_lines"}
    with pytest.raises(ValueError, match="the left image is 10x12, the calibration's 376x240"):
        odometry.track(np.zeros((12, 10), np.uint8), right, 2_000_000_000)
    with pytest.raises(ValueError, match="Odometry.track right: expected a uint8 image"):
        odometry.track(left, right.astype(np.float32), 2_000_000_000)
    # A rejected pair changes nothing: the next one is frame 1.
    assert odometry.track(left, right, 2_000_000_000)[1]["frame_index"] == 1


def test_odometry_and_run_reject_bad_configs(random_packs, camchain, tmp_path):
    model = random_packs / "random_superpoint.vkvopack"
    with pytest.raises(FileNotFoundError, match="config .*nowhere.yaml does not exist"):
        vkvo.Odometry(tmp_path / "nowhere.yaml", camchain, model=model)
    misspelt = tmp_path / "misspelt.yaml"
    misspelt.write_text("tracking:\n  min_num_matches: 30\n")
    with pytest.raises(RuntimeError, match="min_num_matches"):
        vkvo.Odometry(misspelt, camchain, model=model)
    with pytest.raises(RuntimeError, match="euroc.yaml"):  # no camera section, no calibration given
        vkvo.Odometry(EUROC_CONFIG, model=model)
    with pytest.raises(ValueError, match="matcher 'flann': expected superglue or nn"):
        vkvo.Odometry(EUROC_CONFIG, camchain, model=model, matcher="flann")
    with pytest.raises(FileNotFoundError, match="dataset .*no_dataset does not exist"):
        vkvo.run(EUROC_CONFIG, tmp_path / "no_dataset", tmp_path / "out", model=model)
    with pytest.raises(RuntimeError, match="empty_folder"):
        (tmp_path / "empty_folder").mkdir()
        vkvo.run(EUROC_CONFIG, tmp_path / "empty_folder", tmp_path / "out", model=model)


def test_dataset_reads_a_synthetic_sequence(cli, tmp_path):
    sequence = tmp_path / "sequence"
    subprocess.run([cli, "synth", "--out", str(sequence), "--preset", "default", "--frames", "3",
                    "--no-default-events"], check=True, capture_output=True)
    dataset = vkvo.Dataset(sequence)
    assert len(dataset) == 3 and dataset.kind == "euroc"
    left, right, t = dataset[-1]
    assert left.dtype == np.uint8 and left.shape == right.shape and left.ndim == 2
    assert t == dataset.timestamps_ns[2]
    np.testing.assert_array_equal(left, vkvo.imread(dataset.root / "cam0" / "data" / f"{t}.png"))
    assert [frame[2] for frame in dataset] == list(dataset.timestamps_ns)
    assert dataset.groundtruth is not None
    with pytest.raises(IndexError):
        dataset[3]
    assert len(vkvo.Dataset(sequence, first=1)) == 2


def test_run_refuses_a_video_it_cannot_write_before_running(random_packs, cli, tmp_path):
    sequence = tmp_path / "sequence"
    subprocess.run([cli, "synth", "--out", str(sequence), "--preset", "default", "--frames", "2",
                    "--no-default-events"], check=True, capture_output=True)
    model = random_packs / "random_superpoint.vkvopack"
    with pytest.raises(RuntimeError, match=r"video file .*clip\.mkv: unsupported extension '\.mkv'"):
        vkvo.run(EUROC_CONFIG, sequence, tmp_path / "out", model=model, video=tmp_path / "clip.mkv")
    (tmp_path / "taken").write_text("a file where the video's folder would be")
    with pytest.raises(RuntimeError, match=r"video file .*taken/clip\.mp4: cannot create its folder"):
        vkvo.run(EUROC_CONFIG, sequence, tmp_path / "out", model=model, video=tmp_path / "taken" / "clip.mp4")
    assert not (tmp_path / "out").exists()  # the run never started
