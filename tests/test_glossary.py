"""The glossary of docs/architecture.md names what the code calls things: every backquoted name
in its first column is an identifier somewhere in dem_core's source (a word match), so a rename
that leaves the glossary behind fails here, naming the stale entries."""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ARCHITECTURE = ROOT / "docs" / "architecture.md"


def glossary_names(text: str) -> list:
    """The backquoted names of the first column of the table under the "Glossary" heading."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines)
                 if line.lstrip().startswith("#") and "glossary" in line.lower())
    names, in_table = [], False
    for line in lines[start + 1:]:
        if not line.startswith("|"):
            if in_table:
                break                        # the table has ended
            continue
        in_table = True
        first = line.split("|")[1]
        if set(first.strip()) <= set("-: "):
            continue                         # the separator row
        names += re.findall(r"`([^`]+)`", first)
    return names


def dem_core_source() -> str:
    return "\n".join(p.read_text() for p in sorted((ROOT / "dem_core").rglob("*.py")))


def test_the_glossary_table_is_found_and_holds_names():
    names = glossary_names(ARCHITECTURE.read_text())
    assert len(names) > 20 and "pos" in names and "sn" in names, names


def test_every_glossary_name_is_an_identifier_in_dem_core():
    source = dem_core_source()
    missing = [n for n in glossary_names(ARCHITECTURE.read_text())
               if not re.search(r"(?<!\w)" + re.escape(n) + r"(?!\w)", source)]
    assert not missing, f"glossary names not found in dem_core: {missing}"
