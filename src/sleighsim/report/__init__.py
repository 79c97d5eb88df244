"""The report: figures, the page, its templates and findings."""
