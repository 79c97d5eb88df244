"""The claims ledger: judges grouped by the paper's sections, verdict rules, causes."""
