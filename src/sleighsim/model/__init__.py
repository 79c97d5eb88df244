"""The mechanics: parameters, the derived equations, symmetries, the printed form, eps = 0, perturbation."""
