"""The golden suite's files, read and written (docs/reference/golden_formats.md, "File formats" and "What check reads"):

* :mod:`.textformat`, :mod:`.csvformat`, :mod:`.jsonformat` -- the text layer (limits, encoding, line ends)
  and the one CSV and one JSON reader on top of it;
* :mod:`.cases` -- a case folder and an impact-sequence CSV (``expected.csv``, an implementation's output),
  loaded and validated; :mod:`.case_writer` -- the files of a certified case, written;
* :mod:`.spec` -- a case before it is certified (what its ``settings.json`` will say);
* :mod:`.orbits` -- the orbit records and an implementation's values;
* :mod:`.index` -- bug classes, levels and ``cases/index.json``; :mod:`.version` -- the suite's version and
  digest; :mod:`.known_failures` -- the ``--known-failures`` file; :mod:`.export` -- the suite exported.

The lowest layer of the package with :mod:`..boundary` and :mod:`..paths`: it imports no other part of it.
"""
