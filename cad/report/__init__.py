"""Human reports (Markdown + PNG plots) and plots. matplotlib imported lazily."""
