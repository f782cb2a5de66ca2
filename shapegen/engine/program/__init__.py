"""The compiled program of a grammar (:class:`~.interpreter.Program`): its rules, attrs and consts
compiled once at load time, and the derivation of a model from them."""
