"""Algorithm parameters: dataclasses whose fields carry unit, meaning, range and source.

A parameter set validates itself into readable problems (a list of sentences, empty when
all is well); the GUI's parameter panel and the command line's help are generated from
the same field metadata.
"""

import dataclasses
import math
import numbers
import re
from typing import Any

from wakeline.core.errors import InputError


def param(
    default: Any,
    unit: str,
    doc: str,
    lo: float | None = None,
    hi: float | None = None,
    source: str = "",
    choices: tuple[str, ...] | None = None,
    flags: tuple[str, ...] = (),
) -> Any:
    """A dataclass field with its unit, one-line meaning, allowed range and source.

    ``choices`` lists the allowed values of a text field; ``flags`` are extra command-line
    spellings (``--window``) beside the generated ``--field-name``.
    """
    return dataclasses.field(
        default=default,
        metadata={
            "unit": unit,
            "doc": doc,
            "lo": lo,
            "hi": hi,
            "source": source,
            "choices": choices,
            "flags": flags,
        },
    )


# The team's history in a source (sessions, helper branches, pre-registrations): for the
# maintainers, kept in the field; an operator's help and tooltips show the label before it.
_HISTORY = re.compile(r"session ?\d|session\d+_|\bh\d{2,3}\b|prereg")


def shown_source(source: str) -> str:
    """A field's source as the command-line help and the parameter panel show it.

    A paper reference stays as written; a source that tells how the team came to a value
    (sessions, branches, pre-registration files) shows its label ("ours") and where the
    measurement is written, docs/evaluation.md.
    """
    if not _HISTORY.search(source):
        return source
    head = re.split(r"\s*[(;:]", source, maxsplit=1)[0].strip()
    return f"{head} (docs/evaluation.md)" if head else "docs/evaluation.md"


@dataclasses.dataclass(frozen=True)
class Params:
    """Base of all parameter sets."""

    def problems(self) -> list[str]:
        """Readable problems with the values; empty when they are valid."""
        out = []
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            meta = f.metadata
            if isinstance(f.default, bool):
                if not isinstance(value, bool):
                    out.append(f"{f.name} must be true or false, got {value!r}")
                continue
            if isinstance(f.default, str):
                choices = meta.get("choices")
                if not isinstance(value, str):
                    out.append(f"{f.name} must be text, got {value!r}")
                elif choices and value not in choices:
                    out.append(f"{f.name} must be one of {', '.join(choices)}, got {value!r}")
                continue
            if isinstance(f.default, (int, float)):
                if isinstance(value, bool) or not isinstance(value, (int, float)):
                    out.append(f"{f.name} must be a number, got {value!r}")
                    continue
                # Finite first: int(inf) would raise, and 1e400 reads as inf.
                if not math.isfinite(value):
                    kind = "a whole number" if isinstance(f.default, int) else "finite"
                    out.append(f"{f.name} must be {kind}, got {value!r}")
                    continue
                if (
                    isinstance(f.default, int)
                    and not isinstance(f.default, bool)
                    and value != int(value)
                ):
                    out.append(f"{f.name} must be a whole number, got {value!r}")
                    continue
                if isinstance(f.default, int) and abs(value) >= 2**63:
                    out.append(f"{f.name} is outside the range of a whole number, got {value!r}")
                    continue
                unit = f" {meta.get('unit')}" if meta.get("unit") else ""
                if meta.get("lo") is not None and value < meta["lo"]:
                    out.append(f"{f.name} must be at least {meta['lo']}{unit}, got {value}")
                if meta.get("hi") is not None and value > meta["hi"]:
                    out.append(f"{f.name} must be at most {meta['hi']}{unit}, got {value}")
        return out

    def checked(self):
        """Self, or :class:`InputError` listing every problem."""
        problems = self.problems()
        if problems:
            raise InputError("invalid parameters: " + "; ".join(problems))
        return self

    def replace(self, **changes: Any):
        """A copy with some values changed (text values are converted to the field's type)."""
        types = {f.name: type(f.default) for f in dataclasses.fields(self)}
        unknown = [k for k in changes if k not in types]
        if unknown:
            raise InputError(
                f"unknown parameter(s) {', '.join(unknown)}; known: {', '.join(types)}"
            )
        converted = {}
        for key, value in changes.items():
            if isinstance(value, str) and types[key] is not str:
                try:
                    value = _parse(value, types[key])
                except (ValueError, OverflowError):
                    raise InputError(
                        f"{key}: cannot read {value!r} as {types[key].__name__}"
                    ) from None
            converted[key] = value
        return dataclasses.replace(self, **converted)

    @classmethod
    def describe(cls) -> list[dict]:
        """Field descriptions for help texts and the parameter panel."""
        return [
            {"name": f.name, "default": f.default, **f.metadata} for f in dataclasses.fields(cls)
        ]


def _parse(text: str, kind: type) -> Any:
    if kind is bool:
        if text.lower() in ("1", "true", "yes", "on"):
            return True
        if text.lower() in ("0", "false", "no", "off"):
            return False
        raise ValueError(text)
    if kind is int:
        try:
            return int(text)  # exact, however many digits
        except ValueError:
            value = float(text)  # "1e3", "2.0", "inf", "1e400" (= inf)
        # Not finite or not whole: kept as a float so problems() names the parameter.
        return int(value) if math.isfinite(value) and value == int(value) else value
    return kind(text)


def finite_number(value: object, what: str) -> float:
    """``value`` as a float when it is a finite number (not a bool); else ValueError
    "``what`` must be a number / finite, got …" (a value read from a project, say)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{what} must be a number, got {value!r:.60}")
    if not math.isfinite(value):
        raise ValueError(f"{what} must be finite, got {value!r}")
    return float(value)
