"""``train/`` sits on the library, the tasks and ``envs.runs``, never on the command line
(``docs/design.md``, "Layers")."""

from pathlib import Path

TRAIN = Path(__file__).resolve().parents[2] / "train"


def test_training_code_does_not_import_the_command_line():
    """A planted ``from envs.commands ...`` in any module of ``train/`` fails this."""
    offenders = [p.name for p in sorted(TRAIN.glob("*.py"))
                 if any("import" in line and "envs.commands" in line
                        for line in p.read_text().splitlines())]
    assert len(list(TRAIN.glob("*.py"))) > 5 and not offenders, offenders
