"""The plumbing every layer may use: ``checks`` (input checks with errors that name the parameter, its unit and range),
``paths`` (the package's data and the checkout's output folders), ``results`` (results files, keyed caches, run locks),
``versions`` (the versions stored results depend on) and ``plotting`` (the notebooks' figures).

It imports no other layer.
"""
