"""One version: pyproject.toml, ``pivot_ompl.__version__`` and the CHANGELOG's newest section."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pivot_ompl

ROOT = Path(__file__).resolve().parents[1]


def test_the_package_and_pyproject_say_one_version():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert pivot_ompl.__version__ == meta["project"]["version"]


def test_the_changelog_s_newest_section_is_that_version_and_in_order():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    heads = re.findall(r"^## \[(\d+)\.(\d+)\.(\d+)\] - (Unreleased|\d{4}-\d{2}-\d{2})$", text, re.M)
    assert heads, "no '## [x.y.z] - date' section"
    release = ".".join(heads[0][:3])
    version = pivot_ompl.__version__
    # a development version (0.4.0.dev0) is the Unreleased section's; a release has its date
    if ".dev" in version:
        assert version.split(".dev")[0] == release and heads[0][3] == "Unreleased"
    else:
        assert version == release and heads[0][3] != "Unreleased"
    numbers = [tuple(int(x) for x in h[:3]) for h in heads]
    assert numbers == sorted(numbers, reverse=True) and len(set(numbers)) == len(numbers)
    dates = [h[3] for h in heads[1:]]
    assert "Unreleased" not in dates and dates == sorted(dates, reverse=True)
    for section in re.split(r"^## ", text, flags=re.M)[1:]:
        kinds = re.findall(r"^### (.+)$", section, re.M)
        assert set(kinds) <= {"Added", "Changed", "Fixed", "Removed", "Deprecated", "Security"}
