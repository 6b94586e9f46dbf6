"""The generated sections that a claim cites: they stay current (:mod:`docs.freshness.check`).

A section is cited when the README or ``docs/design.md`` states one of its figures as what the
project measures today. Every other section of ``docs/benchmarks.md`` is a dated record. Add a
section here when a claim starts citing it; drop it when no claim does.
"""

#: section name -> where a claim cites it. Not here: ``calibration-placenav-v2``, which the
#: README and the design cite as 0.15.0's (a dated record) until its probe is run
#: (``python -m docs.freshness verify calibration-placenav-v2``, about half an hour); and
#: ``simulator``, whose figures are speeds: the design cites them as measured on their day
CITED: dict[str, str] = {
    "demo": "README: | `d77808d5ebdff7e4` | 0.860 / 0.636 / 9 | 0.964 / 0.828 / 6 | ...",
    "panorama-test": "README: | `PANORAMA`, SIFT | 0.985 [0.981, 0.990] (0.964)",
    "panorama-orb-test": "README: | `PANORAMA_ORB`, ORB | 0.972 [0.959, 0.979] (0.851)",
    "matched-online": "design.md: method is compared with the others at matched numbers of pla",
    "matched-rooms": "design.md: method is compared with the others at matched numbers of pla",
    "seed001-test": "README: **Seed 001 on its paper's camera** (`make seed001`, 4 `test`",
    "corridor": "README: the paper's defaults 0.52, KAZE 0.70 (NetVLAD's image top-1 0.68)",
    "like-test": "README: by top-1 above chance as the data does: corridor Spearman 0.82 […",
    "like-test-matched": "README: Cameras matched on image statistics (`assets/cameras/`) rank…",
    "like-test-rtabmap": "README: corridor Spearman 0.82 [0.78, 0.94], RTAB-Map's loop 0.78 [0.4…",
    "like-test-rtabmap-matched": "design.md: 0.73] through the one matched on `train` (overlapping",
    "like-test-rtabmap-matched-lap": "README: matched, query drive a second lap: 0.70",
    "image-stats": "design.md: them (`placeclust stats`, 'How alike the places look': next",
    "image-stats-100": "design.md: matches across rooms with doors fall to a 90th percentile of",
    "seed001-test-doors": "design.md: location it leaves about as often as frames within a room ma",
    "seed001-test-doors-100": "README: frame (`--doors 1.0 --param max_features=100`) 0.930 [0.91…",
    "panorama-test-doors": "design.md: `PANORAMA` keeps its bar with doors opening at 0.5 m: on t…",
    "leaderboard-val": "design.md: The pilot and its figures are in `docs/benchmarks.md` ('How",
    "compare-placenav-v1": "design.md: (`PANORAMA` and `PANORAMA_ORB` 0.013 [−0.037, 0.073] apart…",
    "agents-carried-grid": "README: **Learned agents** (`make agents-tour`, 20 `test` buildings,",
    "agents-drift": "design.md: over 20 continued errands its dead reckoning ends metres off",
    "score-pilot-val": "design.md: (`docs/benchmarks.md`, 'Tracks: a first pilot'): continued `",
    "lit-panorama": "design.md: Open loop, `PANORAMA` on the same 4 `val` buildings lit (`do",
    "lit-paper": "design.md: (4 buildings: a pilot); the paper's defaults `day>night` +0.",
    "score-pilot-lit-val": "design.md: Closed loop, lit (`docs/benchmarks.md`, 'The tracks in lit…",
    "leaderboard-val-corridor-carried-relocalizer": "design.md: ranks these two (measured again w…",
    "compare-val-corridor-carried": "design.md: [0.53, 0.80], paired −0.033 [−0.217, 0.167], 95–1…",
    "calibration-corridor-carried-val": "design.md: it cuts them. On 6 `val` buildings `oracle-sp…",
    "calibration-tracks-val": "design.md: resolve what the calibration says the track does resolv…",
    "score-placenav-v2": "README: **Errands in buildings never seen** (`make leaderboard`: `pl",
    "leaderboard-placenav-v2-continued": "design.md: - `continued`: by 0.083 [0.017, 0.267], with…",
    "leaderboard-placenav-v2-corridor": "design.md: `PANORAMA_ORB` cuts 5.6 places a room (NMI 0.…",
    "score-placenav-v2-paper": "README: Seed 000's values beat `PANORAMA` on `continued` and e…",
    "leaderboard-val-continued-spot": "design.md: *What the `val` pilot says* (`docs/benchmarks",
    "leaderboard-val-carried-spot": "design.md: *What the `val` pilot says* (`docs/benchmarks",
    "score-pilot-v3-val": "design.md: *What the `val` pilot says* (`docs/benchmarks.md`, '`pla",
    "score-placenav-v3": "design.md: true rooms are below two places a room on the score (−0.150",
    "leaderboard-placenav-v3-corridor": "design.md: corridor, where it cuts 5.6 places a room; b…",
    "score-placenav-v3-doors-nested": "README: at 100 keypoints: +0.196 [0.161, 0.232] over no…",
    "image-stats-matched-corridor": "design.md: keypoints 89.5 against 111 (−19%), next-frame…",
    "score-placenav-v3-paper": "README: seed 000 as published (`--preset paper`, 2.4 places a",
    "compare-v3-localize-continued": "design.md: on any (fixed − learning +0.08 to +0.10 on `con…",
    "compare-v3-localize-changed-night": "design.md: night 35 of 60 on their first step, against…",
    "compare-v3-localize-changed-cloudy": "design.md: on any (fixed − learning +0.08 to +0.10 on…",
    "compare-v3-localize-changed-moved": "design.md: furniture moved, every interval holding 0)…",
    "score-placenav-v4": "design.md: full size on the same 12 `test` buildings (`docs/benchmark",
    "score-placenav-v5": "README: **Errands to a picture** (`make leaderboard-v5`: `placenav-v5`",
    "score-v3-errands15": "design.md: more), and the 12 `test` buildings then resolved six of…",
    "image-stats-matched-rtabmap-train": "design.md: its own is 2.9 pixels at one frame a second…",
    "like-test-matched-night-moved": "README: query drive is another day's as the corridor's is (…",
    "like-test-night-moved": "design.md: [0.81, 0.96] above chance (one light: 0.59), and throu…",
    "score-placenav-v3-door": "design.md: can see (true rooms − `oracle-door:0.25` −0.004 [−0.0…",
}
