"""The forms a parameter of a campaign's space takes (`[[param]]`: `offset`, `define`, `symbol`, `file`,
`source`), one module each, all subclassing `form.Form`; `athrill_sim.tuning.bindings.FORMS` is their table.
This root imports nothing."""
