"""The main job: tour the default world, recognise places online, write a report folder.

``placeclust demo --out DIR`` (``make demo``) writes:

- ``tour.npz``: the recorded frames with ground truth;
- ``floorplan.png``: rooms, names, doors, furniture and the path;
- ``map.png``: the path coloured by the place the online recognizer (seed 000) reported, and
  its topological graph between the places' centroids; ``map_panorama.png``: the same for the
  online recognizer with the settings for 360° panoramas (``placeclust.PANORAMA``: side views,
  the scene-change gate and detection on a 0.75 copy of each frame);
- ``confusion.png``: frames per place and ground-truth room;
- ``tour.gif``: the panoramas over time with the current place and room written on them;
- ``panoramas.png``: a panorama from every room;
- ``report.md``: metrics of the online recognizer (as in the paper and with ``PANORAMA``) and the
  nested mapper (seed 001) against ground truth, also printed on the terminal; then both
  again on the same route seen by the forward camera (``camera="forward"``), the camera
  seed 001 was designed for.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from placeclust import PANORAMA, OnlinePlaceClustering, strict_json

from ..tasks.tour import record_tour
from .figures import save_confusion, save_floor_plan, save_panoramas, save_place_map, save_tour_gif


def run_demo(out: str, scene_seed: int = 0, n_rooms: int = 4, steps: int = 1000,
             seed: int = 0) -> dict[str, dict[str, float]]:
    """Run the main job and write the report folder ``out``; returns the metrics table."""
    from placeclust.runner import evaluate, run

    from .bench_report import format_table

    if steps < 1:
        raise ValueError(f"steps must be positive, got {steps}")
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    tour, plan = record_tour(scene_seed, n_rooms, steps, seed)
    tour.save(str(folder / "tour.npz"), scene_seed=scene_seed, tour_seed=seed)
    save_floor_plan(plan, str(folder / "floorplan.png"), tour.pose,
                    title=f"scene {scene_seed}: {n_rooms} rooms, {steps} steps")
    save_panoramas(tour, str(folder / "panoramas.png"))
    table, results = {}, {}
    for name, algo, label, params in (
            ("online", "online", "online (seed 000)", {}),
            ("online_panorama", "online", "online, PANORAMA settings", PANORAMA),
            ("nested", "nested", "nested (seed 001)", {})):
        results[name] = run(algo, tour.frames, "sift", progress=True, **params)
        table[label] = evaluate(results[name], tour.room)
        np.save(folder / f"assignments_{name}.npy", results[name].assignments)
    # seed 001 ran on a forward-looking monocular camera: the same route seen by one
    forward, _ = record_tour(scene_seed, n_rooms, steps, seed, camera="forward")
    for name, algo, label in (("nested_forward", "nested", "nested (seed 001), forward camera"),
                              ("online_forward", "online", "online (seed 000), forward camera")):
        results[name] = run(algo, forward.frames, "sift", progress=True)
        table[label] = evaluate(results[name], forward.room)
        np.save(folder / f"assignments_{name}.npy", results[name].assignments)
    online = results["online"].assignments
    online_model, panorama_model = results["online"].model, results["online_panorama"].model
    # both ran the "online" algorithm: their models have its place graph
    assert isinstance(online_model, OnlinePlaceClustering)
    assert isinstance(panorama_model, OnlinePlaceClustering)
    save_place_map(plan, tour.pose, online, str(folder / "map.png"),
                   "places found online (seed 000) and their graph", online_model.graph)
    save_place_map(plan, tour.pose, results["online_panorama"].assignments,
                   str(folder / "map_panorama.png"),
                   "places found online, side views and scene changes", panorama_model.graph)
    save_confusion(online, tour.room, tour.room_names, str(folder / "confusion.png"),
                   "online (seed 000): frames per place and room")
    save_tour_gif(tour, online, str(folder / "tour.gif"))
    text = format_table(table)
    (folder / "report.md").write_text(
        f"# placeclust demo\n\nScene seed {scene_seed}, {n_rooms} rooms, {steps} frames of "
        f"512x128 panoramas, SIFT features, tour seed {seed}.\n\n{text}\n\n"
        "precision: clustering precision (purity) as in seed 000 Fig. 2; recall: inverse "
        "purity; ms_per_frame: median latency. PANORAMA settings: only the features within 45 "
        "degrees of the robot's left and right, new places only after a scene change, and "
        "features detected on a 0.75 copy of each frame (map_panorama.png). Forward camera: "
        "the same route seen by one 320x240 perspective camera looking ahead (70 degrees), "
        "the camera seed 001 was designed for.\n")
    (folder / "metrics.json").write_text(strict_json.dumps(table, indent=2))
    print(text)
    print(f"\nreport written to {folder}/")
    return table
