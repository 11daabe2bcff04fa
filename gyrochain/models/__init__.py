"""From a spec to a model one can run: pipeline (derive once, render the printers, the content-keyed
cache), build (the cffi extension, CModel, load), generate (the command's library function), typeset
(the PDF), and files (writing outputs without losing the user's).

Modules: files, build, pipeline, typeset, generate.  May import: printers, derive, chainspec (the
layers of [tool.importlinter] in pyproject.toml).
"""
