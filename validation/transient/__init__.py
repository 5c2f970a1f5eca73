"""Transient chaos after the crisis (Section 4, Figs. 9-11): engine, analysis, figures."""
