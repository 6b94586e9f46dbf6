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


def test_sensor_costs_name_every_effect_at_every_size(monkeypatch):
    from envs.commands import speed

    monkeypatch.setattr(speed, "SENSOR_SIZES", ((32, 24),))
    table = speed.sensor_table(steps=2, rounds=1)
    for name in speed.EFFECTS:
        row = next(line for line in table.splitlines() if line.startswith(f"| {name} |"))
        assert float(row.split("|")[2]) > 0  # a share of env.step, measured
