"""The grammar engine: the interpreter that derives a Model from a parsed grammar.

:func:`~shapegen.engine.grammar_api.load_grammar` is the entry point; the data it produces lives
in :mod:`shapegen.model`.
"""
