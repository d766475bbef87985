"""LodForge's Python package.

Placeholder for the batch branch: the Python module branch's ``__init__.py`` (the compiled API) replaces
this file when both are merged. ``lodforge.dask_batch`` does not need anything from here.
"""
