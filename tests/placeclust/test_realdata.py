import os

import cv2
import numpy as np
import pytest

from placeclust.datasets import DatasetError, ImageFolder, write_image_folder
from placeclust.realdata import (
    cluster_folder,
    dataset_kind,
    fingerprint,
    localize_queries,
    run_dataset,
    save_place_strips,
    vpr_bench,
    with_queries,
)
from placeclust.synthetic import places
from placeclust.vprbench import VPRBench, write_vpr_bench


@pytest.fixture(scope="module")
def three_places():
    return places(3)


def _folder(path, frames, truth, prefix="room"):
    write_image_folder(path, frames, [f"{prefix}{r}" for r in truth])
    return ImageFolder(path)


def test_a_labelled_folder_is_mapped_and_scored(tmp_path, three_places):
    frames, truth = three_places
    run = cluster_folder("online", _folder(tmp_path, frames, truth), "orb")
    assert run.metrics["precision"] == 1.0 and run.metrics["n_rooms"] == len(set(truth))
    assert run.metrics["frames"] == run.metrics["labelled_frames"] == len(frames)


def test_without_labels_a_folder_gives_places_graph_and_latency(tmp_path, three_places):
    frames, _ = three_places
    write_image_folder(tmp_path, frames)
    run = cluster_folder("online", ImageFolder(tmp_path), "orb")
    assert {"n_places", "edges", "ms_per_frame"} <= set(run.metrics)
    assert "precision" not in run.metrics


def test_an_offline_recognizer_is_given_the_folder_whole(tmp_path, three_places):
    frames, truth = three_places
    run = cluster_folder("kmeans", _folder(tmp_path, frames, truth), "orb", n_clusters=2)
    assert run.metrics["n_places"] == 2


def test_queries_are_right_where_their_place_holds_their_label(tmp_path, three_places):
    frames, truth = three_places
    mapped = _folder(tmp_path / "map", frames, truth)
    query = _folder(tmp_path / "query", frames[::-1], truth[::-1])
    run = with_queries(cluster_folder("online", mapped, "orb"), mapped, query)
    assert run.metrics["query_top1"] == 1.0 and run.metrics["query_recall@1"] == 1.0
    other = _folder(tmp_path / "other", frames, truth, prefix="hall")
    with pytest.raises(ValueError, match="share no label"):
        with_queries(cluster_folder("online", mapped, "orb"), mapped, other)


def test_queries_alone_or_tracked_and_a_recognizer_that_cannot_localize(three_places):
    frames, _ = three_places
    model = cluster_folder("online", frames, "orb").result.model
    for alone in (False, True):
        result, ranked = localize_queries(model, frames, rank=2, alone=alone)
        assert len(result.assignments) == len(frames) and all(len(r) == 2 for r in ranked)
        assert all(r[0] == p for r, p in zip(ranked, result.assignments))
    kmeans = cluster_folder("kmeans", frames, "orb", n_clusters=2).result.model
    with pytest.raises(ValueError, match="cannot localize"):
        localize_queries(kmeans, frames)


def test_a_vpr_bench_folder_is_mapped_from_ref_and_scored_on_query(tmp_path, three_places):
    frames, truth = three_places
    refs = [np.flatnonzero(truth == r).tolist() for r in truth]
    write_vpr_bench(tmp_path, frames, frames, refs)
    run = vpr_bench("online", VPRBench(tmp_path), "orb")
    assert run.metrics["query_top1"] == 1.0 and run.metrics["query_n_queries"] == len(frames)
    assert 0 < run.metrics["query_chance"] < 1
    assert dataset_kind(tmp_path) == "vpr-bench"
    _, stored = run_dataset("online", tmp_path, "orb")
    assert (stored == -1).all()


def test_a_benchmark_data_set_needs_labels_or_the_vpr_bench_layout(tmp_path, three_places):
    frames, truth = three_places
    write_image_folder(tmp_path, frames)
    with pytest.raises(DatasetError, match="no labels.csv"):
        dataset_kind(tmp_path)
    _folder(tmp_path, frames, truth)
    assert dataset_kind(tmp_path) == "images"


def test_the_fingerprint_changes_with_the_files(tmp_path, three_places):
    frames, truth = three_places
    folder = _folder(tmp_path, frames, truth)
    before = fingerprint(tmp_path)
    assert fingerprint(tmp_path) == before
    os.utime(folder.files[0], ns=(1, 1))
    assert fingerprint(tmp_path) != before


def test_place_strips_show_each_place_in_a_row(tmp_path, three_places):
    frames, truth = three_places
    save_place_strips(frames, truth, tmp_path / "places.png", per_place=2, height=20)
    picture = cv2.imread(str(tmp_path / "places.png"))
    assert picture.shape[0] == len(set(truth)) * (20 + 2)
