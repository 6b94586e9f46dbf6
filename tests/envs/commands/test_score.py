"""``placeclust score``: tracks normalized between a floor and a ceiling, one suite score,
recognizers paired on it, and the calibration recognizers' resolution."""

from envs.commands import score
from envs.runs.results import write_results

from .test_compare import PROVENANCE, SETTINGS, _row


def _track_file(tmp_path, track, success):
    """A track's results: the floor, the ceiling and two recognizers on four buildings."""
    rows = []
    for name, per_building in success.items():
        rows += [_row(name, s, per_building[s], 0.9) for s in range(4)]
    path = tmp_path / track / "results.json"
    write_results(path, rows, list(success), {**SETTINGS, "track": track}, PROVENANCE)
    return path


def test_the_suite_score_normalizes_tracks_and_pairs_two_recognizers(tmp_path, capsys):
    one = [[1, 1, 1, 1]] * 4
    half = [[1, 1, 0, 0]] * 4
    zero = [[0, 0, 0, 0]] * 4
    files = [_track_file(tmp_path, "carried", {"none": zero, "oracle": one, "good": one,
                                                "poor": half}),
             _track_file(tmp_path, "continued", {"none": half, "oracle": one, "good": one,
                                                 "poor": half})]
    assert score.main([*map(str, files), "--pair", "good", "poor"]) == 0
    out = capsys.readouterr().out
    # carried: poor is halfway; continued: poor is at the floor
    assert "| poor | 0.50 [0.50, 0.50] | 0.50 [0.50, 0.50] | 0.25 [0.25, 0.25] |" in out
    assert "| good | 1.00 [1.00, 1.00] | 1.00 [1.00, 1.00] | 1.00 [1.00, 1.00] |" in out
    assert "**0.750 [0.750, 0.750]**" in out and "the interval excludes 0" in out


def test_the_suite_score_refuses_a_track_without_its_floor_or_twice(tmp_path, capsys):
    one = [[1, 1, 1, 1]] * 4
    path = _track_file(tmp_path, "carried", {"oracle": one, "good": one})
    assert score.main([str(path)]) == 2
    assert "no 'none' rows" in capsys.readouterr().err
    assert score.main([str(path), str(path), "--floor", "good"]) == 2
    assert "two files of track 'carried'" in capsys.readouterr().err


def test_calibration_gives_each_tracks_resolution_and_draws_its_curves(tmp_path, capsys):
    one, zero = [[1, 1, 1, 1]] * 4, [[0, 0, 0, 0]] * 4
    mixed = [[1, 1, 1, 1], [1, 0, 1, 1], [1, 1, 1, 1], [1, 1, 0, 1]]  # 2 of 16 lost: unsure
    files = [_track_file(tmp_path, "carried", {
        "none": zero, "oracle": one, "oracle-noise:0.05": mixed,
        "oracle-noise:0.2": [[1, 0, 0, 0]] * 4, "oracle-split:2": one}),
        _track_file(tmp_path, "continued", {"none": zero, "oracle": one,
                                            "oracle-noise:0.05": one})]
    figure = tmp_path / "curves.png"
    assert score.main([*map(str, files), "--calibration", str(figure)]) == 0
    out = capsys.readouterr().out
    assert "| carried | oracle-noise:0.2 | 0.25 [0.25, 0.25] | -0.750 [-0.750, -0.750] |" in out
    # the smallest error told from the true rooms; a split that keeps every boundary is not
    assert "carried: noise 0.2, split none up to 2; continued: noise none up to 0.05." in out
    assert figure.stat().st_size > 10_000
    assert score.main([str(files[1]), "--floor", "none", "--calibration",
                               str(figure)]) == 0  # a track with calibration rows alone
    plain = _track_file(tmp_path / "p", "carried", {"none": zero, "oracle": one})
    assert score.main([str(plain), "--calibration", str(tmp_path / "x.png")]) == 2
    assert "no calibration recognizer" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()
