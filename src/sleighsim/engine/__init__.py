"""Integration: heyoka integrators, the integrate entry point, Poincare sections, transients, peers."""
