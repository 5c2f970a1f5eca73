"""The vocabulary every layer of gear-rattle speaks; it imports nothing else of the project.

===================  ==========================================================================
:mod:`.params`       the model's parameters (:class:`Params`, Eqs. 3-6 and 11) and their checks
:mod:`.status`       how an orbit and a flight search end (:class:`Status`, :class:`FlightOutcome`)
:mod:`.results`      the result types every track returns (:class:`ImpactSequence`, ...)
:mod:`.registry`     the tracks' names (:data:`TRACKS`) and the numerical tracks' loaders
:mod:`.jax_config`   the project's JAX set-up (float64; :func:`use_cpu_devices`)
===================  ==========================================================================

The closed-form map (:mod:`gear_rattle.mapimpl`), the numerical tracks
(:mod:`gear_rattle.reference`) and the analyses (:mod:`gear_rattle.validation`) import from here;
this package imports none of them (docs/architecture.md).
"""
