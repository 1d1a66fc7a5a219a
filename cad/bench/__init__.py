"""Benchmarks: error against time for every computation with an accuracy knob."""
