"""Reports: bench results on disk (`results`: result.json, waveforms.csv, plots, grids, failure records, the
pages and the index), ASAM MDF4 waveforms (`mdf`), regression against blessed references (`regression`), the
pages in a headless browser (`browser`)."""
