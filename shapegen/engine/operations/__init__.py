"""Shape operations compiled into closures, each at one width or two: the one registry of
operations (:mod:`~.registry`: each operation's one-shape form and batch form), the compiler
of rule bodies that dispatches every item through it (:mod:`~.compiler`), and the operations
themselves (:mod:`~.rule_items`, :mod:`~.template_primitives`, :mod:`~.cga`)."""
