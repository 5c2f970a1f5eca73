"""The generated validation report (``gear-rattle report``): every number in it is computed by the run
that writes it; the paper's own values are the only typed-in numbers, each cited."""
