"""Workflow operations: run logging, run costs (measured and estimated), the config reference,
result-tree comparison and verdict stability. They serve the workflow and its developers; nothing in
the science modules (model, integrators, scenes) imports this package (the report takes its run-cost
figure from :mod:`sleighsim.report.figures.costs`)."""
