"""CGA's expressions compiled into closures (:class:`~.compiler.ExpressionCompiler`): the
operators on values, arrays, and the built-in functions, from pure maths to the ones that read
the shape, the project's files and the other shapes."""
