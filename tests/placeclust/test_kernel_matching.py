import cv2
import numpy as np
import pytest

from placeclust.kernel import UnionKernel
from placeclust.matching import dice_eq4, knn2, ratio_matches, similarity_eq1


def unit(rng, n, d=16):
    x = rng.normal(size=(n, d)).astype(np.float32)
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def test_union_kernel_weights_after_a_known_sequence():
    rng = np.random.default_rng(0)
    a = unit(rng, 5)
    b = np.concatenate([a[:3], unit(rng, 2)])  # 3 features seen again, 2 new
    k = UnionKernel(a, binary=False)
    k.update(b)
    assert len(k) == 7
    np.testing.assert_array_equal(k.weights, [2, 2, 2, 1, 1, 1, 1])
    k.update(b)
    np.testing.assert_array_equal(k.weights, [3, 3, 3, 1, 1, 2, 2])


def test_kernel_is_pruned_to_capacity_keeping_heavy_features():
    rng = np.random.default_rng(1)
    a = unit(rng, 6)
    k = UnionKernel(a, binary=False, capacity=8)
    k.update(np.concatenate([a[:2], unit(rng, 6)]))
    assert len(k) == 8
    assert k.weights.max() == 2 and (k.weights == 2).sum() == 2


def test_ratio_matches_and_eq1_eq4():
    rng = np.random.default_rng(2)
    a = unit(rng, 20)
    q, t = ratio_matches(a, a, binary=False)
    np.testing.assert_array_equal(q, t)
    assert len(q) == 20
    assert similarity_eq1(a, a, False) > 0.999
    assert dice_eq4(10, 20, 20) == 0.5 and dice_eq4(0, 0, 0) == 0.0
    dist, idx = knn2(a[:3], a[:1], False)  # a single train row: no second neighbour
    assert np.all(idx[:, 1] == -1) and np.all(np.isinf(dist[:, 1]))


@pytest.fixture(params=[1, 4], ids=["one-thread", "split-in-four"])
def cv_threads(request):
    """OpenCV's thread count, which also splits placeclust's matching; restored afterwards."""
    before = cv2.getNumThreads()
    cv2.setNumThreads(request.param)
    yield request.param
    cv2.setNumThreads(before)


def test_float_knn2_agrees_with_brute_force(cv_threads):
    """The two nearest train rows and their Euclidean distances, nearest first, whether the
    query rows are matched in one piece or split over threads (600 rows: four parts)."""
    rng = np.random.default_rng(5)
    query, train = unit(rng, 600), unit(rng, 90)
    train[:10] = query[:10] + 0.05 * train[:10]  # some near-duplicates, as in a union kernel
    train /= np.linalg.norm(train, axis=1, keepdims=True)
    full = np.linalg.norm(query[:, None, :] - train[None, :, :], axis=2)
    expected = np.argsort(full, axis=1)[:, :2]
    dist, idx = knn2(query, train, False)
    np.testing.assert_array_equal(idx, expected)
    np.testing.assert_allclose(dist, np.take_along_axis(full, expected, 1), atol=1e-5)
    dist, idx = knn2(query[:3], train[:2], False)  # two train rows: both, in order
    np.testing.assert_array_equal(np.sort(idx, axis=1), [[0, 1]] * 3)
    assert np.all(dist[:, 0] <= dist[:, 1])
    dist, idx = knn2(query, train[:1], False)  # one train row: the second column is empty
    assert np.all(idx == [0, -1]) and np.all(np.isinf(dist[:, 1]))


def test_binary_matching():
    rng = np.random.default_rng(3)
    a = rng.integers(0, 256, (30, 32), dtype=np.uint8)
    q, t = ratio_matches(a, a, binary=True)
    np.testing.assert_array_equal(q, t)
    dist, idx = knn2(a[:2], a[:1], True)
    assert idx[0, 0] == 0 and np.isinf(dist[0, 1])


def test_contrast_normalization_keeps_features_in_dim_light():
    """At a third of the light SIFT loses most keypoints on raw frames, not after CLAHE."""
    import cv2
    import pytest

    from placeclust.features import FeatureExtractor
    from placeclust.synthetic import textured

    bright = cv2.cvtColor(textured(1), cv2.COLOR_RGB2GRAY)
    dim = (bright * 0.3).astype(np.uint8)
    raw, clahe = FeatureExtractor("sift", normalize=None), FeatureExtractor("sift")
    assert len(raw.extract(dim)) < 0.5 * len(raw.extract(bright))
    assert len(clahe.extract(dim)) > 0.8 * len(clahe.extract(bright))
    with pytest.raises(ValueError, match="unknown normalize 'gamma'"):
        FeatureExtractor("sift", normalize="gamma")


def test_scaled_detection_reports_keypoints_in_frame_pixels():
    """A frame twice the size detected at scale 0.5 gives the features of the frame itself, at
    the big frame's pixel coordinates (centres map as (x + 0.5) / scale - 0.5)."""
    import cv2
    import pytest

    from placeclust.features import FeatureExtractor
    from placeclust.synthetic import textured

    gray = cv2.cvtColor(textured(3), cv2.COLOR_RGB2GRAY)
    big = cv2.resize(gray, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST)
    full = FeatureExtractor("orb", scale=1.0).extract(gray)
    half = FeatureExtractor("orb", scale=0.5).extract(big)
    assert len(full) > 50
    np.testing.assert_array_equal(half.descriptors, full.descriptors)
    np.testing.assert_allclose(half.xy, 2 * full.xy + 0.5, atol=1e-4)
    assert FeatureExtractor("sift").scale == 1.0
    with pytest.raises(ValueError, match="scale must be in"):
        FeatureExtractor("sift", scale=1.5)


def test_side_view_keeps_the_keypoints_at_the_robots_left_and_right():
    """``view="sides"`` keeps, of the whole frame's features, those within 45° of the robot's
    left (column W/4) and right (3W/4): the same keypoints, no others."""
    import cv2
    import pytest

    from placeclust.features import FeatureExtractor
    from placeclust.synthetic import textured

    gray = cv2.cvtColor(textured(5), cv2.COLOR_RGB2GRAY)
    width = gray.shape[1]
    full = FeatureExtractor("sift").extract(gray)
    sides = FeatureExtractor("sift", view="sides").extract(gray)
    x = full.xy[:, 0]
    inside = (np.abs(x - width / 4) < width / 8) | (np.abs(x - 3 * width / 4) < width / 8)
    assert 0 < inside.sum() < len(full)
    np.testing.assert_array_equal(sides.xy, full.xy[inside])
    np.testing.assert_array_equal(sides.descriptors, full.descriptors[inside])
    with pytest.raises(ValueError, match="unknown view 'front'"):
        FeatureExtractor("sift", view="front")
