"""The original HIVEX release's own records read as data: its plot pages' curves and average sheets.

pdfpage.py (a matplotlib PDF page as pdfminer.six reads it), pdfplot.py (line panels: means and bands) and
heatmap.py (annotated heatmaps) read the PDFs; digitise.py writes hivex_dsl/data/original-curves.json.xz from
them; curves.py loads it (:func:`~hivex_dsl.evaluation.original.curves.original_curves`); evidence.py reads the
decision periods, budgets and learning points the curves show; compare.py sets a run's or a record's curves (every
training seed) beside them, the one measure at 10, 25, 50 and 100% of the original's budget; tail.py pools each panel
over the last tenth of the budget, ours and the original's; figure.py draws them.
"""
