"""Reading and writing track files (SPEC §1)."""

from wakeline.core.io.formats import FAMILIES, FORMATS, parse_mapping, resolve
from wakeline.core.io.mtad import label_points, read_association_table
from wakeline.core.io.reader import (
    ImportResult,
    import_to_csv,
    inspect_file,
    nothing_imported,
    parse_zone,
    read_points,
)
from wakeline.core.io.sniff import Sniff, sniff
from wakeline.core.io.writer import (
    atomic_path,
    check_outputs,
    write_csv,
    write_json,
    write_points,
)

__all__ = [
    "FAMILIES",
    "FORMATS",
    "ImportResult",
    "Sniff",
    "atomic_path",
    "check_outputs",
    "import_to_csv",
    "inspect_file",
    "label_points",
    "nothing_imported",
    "parse_mapping",
    "parse_zone",
    "read_association_table",
    "read_points",
    "resolve",
    "sniff",
    "write_csv",
    "write_json",
    "write_points",
]
