"""The controller layer: `suite` (`hako test`), `search` (where parameter sets come from) and `campaign` (the
parameter search), over what they share at this top level (benches, runners, executors, options). This
root imports nothing."""
