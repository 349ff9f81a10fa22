"""The map's colours: one per layer or sensor, and distinct ones per selected batch."""

#: Layer colours (one per sensor of a source layer, one per derived layer).
PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf")
#: Distinct colours for batches of a selection (or a layer coloured by batch): tab10 and
#: darker companions, all readable on white; consecutive entries differ in hue.
BATCH_PALETTE = (
    "#1f77b4",
    "#d62728",
    "#2ca02c",
    "#ff7f0e",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
    "#7f7f7f",
    "#393b79",
    "#ad494a",
    "#637939",
    "#8c6d31",
    "#7b4173",
    "#3182bd",
    "#e6550d",
    "#31a354",
    "#756bb1",
    "#636363",
)
