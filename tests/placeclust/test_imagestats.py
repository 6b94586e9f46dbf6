import numpy as np
import pytest

from placeclust.datasets import write_image_folder
from placeclust.imagestats import image_stats, main, revisit_stats, revisit_table, stats_table
from placeclust.synthetic import places, textured

LABELLED = ("across_median", "across_p90", "across_pairs", "within_median", "within_p90",
            "within_pairs")


@pytest.fixture(scope="module")
def tour():
    return places(6, n_places=2)  # frames 0-5 show place 0, frames 6-11 place 1


class CountingFrames:
    """A lazy sequence, as an image folder is, that counts the reads of each frame."""

    def __init__(self, frames):
        self.frames, self.reads = frames, np.zeros(len(frames), int)

    def __len__(self):
        return len(self.frames)

    def __getitem__(self, t):
        self.reads[t] += 1
        return self.frames[t]


def test_identical_views_of_a_place_match_more_than_views_of_two_places():
    frames = [textured(1)] * 6 + [textured(2)] * 6
    stats = image_stats(frames, [0] * 6 + [1] * 6, features="orb", pairs=10)
    assert stats["within_median"] == stats["keypoints_median"] > 100
    assert stats["across_p90"] < stats["within_median"] / 10


def test_jittered_views_of_a_place_match_more_than_other_places(tour):
    frames, truth = tour
    stats = image_stats(frames, truth, features="sift", pairs=20)
    assert stats["frames"] == 12 and stats["across_pairs"] == stats["within_pairs"] == 20
    assert stats["keypoints_p10"] <= stats["keypoints_median"] <= stats["keypoints_p90"]
    assert stats["within_median"] > 10 * max(stats["across_p90"], 1)
    assert stats["next_median"] > stats["across_p90"]


def test_across_and_within_keys_only_with_labels(tour):
    frames, truth = tour
    plain = image_stats(frames, features="orb", pairs=3)
    assert not set(LABELLED) & set(plain)
    assert plain["next_pairs"] == 3  # at most `pairs` consecutive pairs, spread out
    labelled = image_stats(frames, truth, features="orb", pairs=3)
    assert set(LABELLED) <= set(labelled)
    assert {k: labelled[k] for k in plain} == plain


def test_same_seed_same_figures_and_each_frame_read_once(tour):
    frames, truth = tour
    lazy = CountingFrames(frames)
    first = image_stats(lazy, truth, features="orb", pairs=15, seed=3)
    assert lazy.reads.tolist() == [1] * len(frames)
    assert image_stats(frames, truth, features="orb", pairs=15, seed=3) == first


def test_a_sparser_detector_keeps_fewer_keypoints_and_matches(tour):
    frames, truth = tour
    full = image_stats(frames, truth, features="sift", pairs=10)
    sparse = image_stats(frames, truth, features="sift", pairs=10, max_features=30)
    assert full["keypoints_median"] > 30 and sparse["keypoints_p90"] <= 30
    assert sparse["next_median"] <= 30 and sparse["within_median"] < full["within_median"]


def test_no_place_spanning_the_gap_gives_no_within_pairs(tour):
    frames, _ = tour
    stats = image_stats(frames[:6], [0, 0, 1, 1, 2, 2], features="orb", pairs=5)
    assert stats["within_pairs"] == 0 and np.isnan(stats["within_median"])
    assert stats["across_pairs"] == 5


@pytest.mark.parametrize("kwargs, reason", [
    (dict(frames=1), "at least 2 frames"),
    (dict(labels=[0, 1, 0]), "labels must be 12 integers"),
    (dict(labels=[0] * 6 + [-1] * 6), "1 place"),
    (dict(pairs=0), "pairs must be at least 1"),
    (dict(features="brisk"), "unknown features 'brisk'"),
    (dict(max_features=0), "max_features"),
])
def test_bad_input_says_what_is_wrong(tour, kwargs, reason):
    frames, truth = tour
    args = dict(frames=frames, labels=truth, features="orb")
    if kwargs.get("frames") == 1:
        kwargs = dict(frames=frames[:1], labels=None)
    args.update(kwargs)
    with pytest.raises(ValueError, match=reason):
        image_stats(**args)


def test_the_table_has_a_row_per_sequence_and_dashes_where_absent():
    table = stats_table({"sim": {"frames": 12, "keypoints_median": 480.0, "next_median": 300.0,
                                 "next_p90": 320.5, "across_median": 4.0, "across_p90": 9.0,
                                 "within_median": 250.0, "within_p90": float("nan")},
                         "real": {"frames": 3, "keypoints_median": 90.0}})
    lines = table.splitlines()
    assert len(lines) == 4 and lines[0].startswith("| sequence | frames |")
    assert lines[2] == "| sim | 12 | 480 | 300 / 320.5 | 4 / 9 | 250 / – |"
    assert lines[3] == "| real | 3 | 90 | – / – | – / – | – / – |"


def test_the_command_prints_a_table_of_a_folder_and_a_tour(tmp_path, tour, capsys):
    frames, truth = tour
    write_image_folder(tmp_path / "images", frames, labels=[f"room{p}" for p in truth])
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    assert main(["--images", str(tmp_path / "images"), "--tour", str(tmp_path / "tour.npz"),
                 "--features", "orb", "--pairs", "5"]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith(f"| {tmp_path}")]
    assert len(rows) == 2 and all(" 12 | " in r and "– / –" not in r for r in rows)


def test_stride_keeps_every_kth_frame_of_a_tour_and_says_so(tmp_path, tour, capsys):
    """A tour steps 0.1 s; ``--stride`` spaces its frames as a data set's may be. The folder
    keeps its own frames."""
    frames, truth = tour
    write_image_folder(tmp_path / "images", frames, labels=[f"room{p}" for p in truth])
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    assert main(["--images", str(tmp_path / "images"), "--tour", str(tmp_path / "tour.npz"),
                 "--features", "orb", "--pairs", "5", "--stride", "3"]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith(f"| {tmp_path}")]
    folder, strided = rows
    assert " | 12 | " in folder and "(every 3) | 4 | " in strided
    with pytest.raises(SystemExit) as exit_:
        main(["--tour", str(tmp_path / "tour.npz"), "--stride", "0"])
    assert exit_.value.code == 2 and "--stride must be at least 1" in capsys.readouterr().err


def test_bad_input_gives_one_error_line_status_2_and_writes_nothing(tmp_path, capsys):
    docs = tmp_path / "bench.md"
    np.savez(tmp_path / "empty.npz", other=np.zeros(3))
    for argv in (["--images", str(tmp_path / "missing")], ["--tour", str(tmp_path / "empty.npz")]):
        assert main([*argv, "--docs", str(docs)]) == 2
        err = capsys.readouterr().err
        assert err.startswith("error: ") and len(err.strip().splitlines()) == 1
    assert not docs.exists()
    for argv in ([], ["--images", "x", "--max-features", "0"]):  # no input; a cap below 1
        with pytest.raises(SystemExit) as exit_:
            main(argv)
        assert exit_.value.code == 2
        assert "max-features" in capsys.readouterr().err or not argv


def test_docs_writes_the_section_and_keeps_the_rest(tmp_path, tour, capsys):
    frames, _ = tour
    write_image_folder(tmp_path / "images", frames[:4])
    docs = tmp_path / "bench.md"
    docs.write_text("# Benchmarks\n\nKept.\n\n<!-- BEGIN GENERATED image-stats -->\nold\n"
                    "<!-- END GENERATED image-stats -->\n")
    argv = ["--images", str(tmp_path / "images"), "--features", "orb", "--docs", str(docs)]
    assert main(argv, prog="placeclust stats") == 0
    text = docs.read_text()
    assert "Kept." in text and "old" not in text and "| sequence |" in text
    assert "`placeclust stats --images" in text
    assert text.count("<!-- BEGIN GENERATED image-stats -->") == 1


def test_a_query_matches_its_own_place_on_the_other_drive_more_than_another(tour):
    """The revisit count follows the ground truth: pointed at the query's own place it is
    higher than pointed at the other place (fault caught: matching a fixed reference)."""
    frames, truth = tour
    ref, query = frames[::2], frames[1::2]  # 3 views a place on each drive
    own = [np.flatnonzero(truth[::2] == t).tolist() for t in truth[1::2]]
    other = [np.flatnonzero(truth[::2] != t).tolist() for t in truth[1::2]]
    right, wrong = (revisit_stats(ref, query, gt, "orb") for gt in (own, other))
    assert right["revisit_pairs"] == 6 and right["revisit_median"] > wrong["revisit_median"]
    none = revisit_stats(ref, query, [[]] * 6, "orb")
    assert none["revisit_pairs"] == 0 and np.isnan(none["revisit_median"])
    assert revisit_stats(ref, query, own, "orb", pairs=2)["revisit_pairs"] == 2
    table = revisit_table({"a": right, "b": none})
    assert "| a | 6 |" in table and "| b | 0 | – / – |" in table
    with pytest.raises(ValueError, match="ground truth for 5 queries, but 6"):
        revisit_stats(ref, query, own[:5], "orb")
