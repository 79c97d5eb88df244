"""Analysis of orbits: spectra, fits, windows, and the precision ladder's observables."""
