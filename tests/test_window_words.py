"""The engine's advice in the window's words (h118: a refused origin read "the import
dialog's Origin of x/y metres field,10': latitude must be …" — the flag's quoted value
was cut at its comma; a suggested mapping read "the import dialog's Column mapping field
the import dialog's Column mapping field …", once per --map)."""

from hypothesis import given
from hypothesis import strategies as st

from wakeline.app.window_words import window_words


@given(value=st.from_regex(r"[0-9A-Za-z.,;: °NSEW-]{0,20}", fullmatch=True))
def test_a_refused_origin_keeps_its_value_whole(value):
    text = window_words(f"--origin '{value}': latitude must be within ±90°")
    assert text == (
        f"the import dialog's Origin of x/y metres field ('{value}'): latitude must be within ±90°"
    )


@given(
    pairs=st.lists(
        st.tuples(
            st.sampled_from(["time", "batch", "lon", "lat", "range", "bearing"]),
            st.one_of(
                st.from_regex(r"[A-Za-z][A-Za-z0-9_]{0,10}", fullmatch=True),  # bare
                st.from_regex(r"[A-Za-z][A-Za-z0-9_]{0,4} \([a-z]{1,3}\)", fullmatch=True),
            ),
        ),
        min_size=2,
        max_size=5,
    )
)
def test_a_suggested_mapping_is_one_field_with_its_choices(pairs):
    flags = " ".join(f"--map '{k}={v}'" if " " in v else f"--map {k}={v}" for k, v in pairs)
    text = window_words(f"the columns may be: {flags} (check them)")
    want = ", ".join(f"{k}={v}" for k, v in pairs)
    assert text == f"the columns may be: the import dialog's Column mapping ({want}) (check them)"
    assert "--" not in text
