"""``placeclust speed`` runs end to end and writes its table (a smoke test: no timing is
asserted, only what the table says)."""

import re

import pytest

from envs.commands import speed


def test_the_simulator_benchmark_writes_its_ratios(tmp_path, capsys):
    doc = tmp_path / "benchmarks.md"
    speed.main(["--steps", "2", "--rounds", "1", "--docs", str(doc)])
    text = doc.read_text()
    assert "BEGIN GENERATED simulator" in text and "placeclust speed" in text
    row = r"^\| (\d+x\d+) \| (\d+) \| ([^|]+) \| .* \*\*([\d.]+)x\*\* \| ([\d.]+) \|"
    rows = re.findall(row, text, re.M)
    assert [(size, rooms) for size, rooms, *_ in rows] == [
        (f"{w}x{h}", str(r)) for w, h, r, _ in speed.ROWS]
    assert [world.strip() for _, _, world, *_ in rows][-2:] == [
        "local_light=True", "local_light=True lighting=night"]
    assert all(float(r) > 0 and float(cores) > 0 for *_, r, cores in rows)
    assert re.search(r"\*\*[\d.]+x\*\* with single-threaded workers", text)
    assert "env.step / floor" in capsys.readouterr().out


def test_bad_counts_are_refused():
    with pytest.raises(SystemExit):
        speed.main(["--steps", "0"])
