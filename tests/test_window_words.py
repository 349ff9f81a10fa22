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


def test_the_clean_summarys_set_flag_names_the_parameters_place_in_the_window():
    """Review h209: the window's log said "--set speed.split_at_breaks=true" (a command
    line's flag); the window names the parameter's place, in English and in Chinese."""
    import pandas as pd

    from wakeline.app.core_text import translate
    from wakeline.core.clean import clean
    from wakeline.core.pipeline import STEPS, StepResult
    from wakeline.core.words import render

    rows = [(k * 10.0, 122.0, 30.0 + k * 6e-4) for k in range(60)]
    rows += [(600 + k * 10.0, 122.04, 30.01 + k * 6e-4) for k in range(60)]
    t0 = pd.Timestamp("2024-05-01", tz="UTC")
    pts = pd.DataFrame(
        {
            "sensor": "R1",
            "batch": "5",
            "time": [t0 + pd.Timedelta(seconds=s) for s, _, _ in rows],
            "lon": [x for _, x, _ in rows],
            "lat": [y for _, _, y in rows],
        }
    )
    summary = STEPS["clean"].summary(StepResult("clean", [], clean(pts).report, {}))
    english = render(summary, lambda t: t)
    assert "--set speed.split_at_breaks=true" in english  # the command line's words
    shown = window_words(english)
    assert "--set" not in shown
    assert "(turning on Parameters ▸ Cleaning ▸ speed ▸ split_at_breaks splits there)" in shown
    zh = translate(shown, "zh_CN")
    assert "参数 ▸ 清洗 ▸ speed ▸ split_at_breaks" in zh and "Parameters" not in zh
    # the summary already in Chinese (Qt's catalog), then the window's words
    zh_summary = "；保留了 1 个断点（--set speed.split_at_breaks=true 会在此拆分）"
    assert translate(window_words(zh_summary), "zh_CN") == (
        "；保留了 1 个断点（参数 ▸ 清洗 ▸ speed ▸ split_at_breaks = true 会在此拆分）"
    )
