"""The terms of a study's prediction equations: arithmetic expressions of
its inputs (a random variable, or the swept setting by its name) and
numbers with + - * / ^ and brackets, each input in the unit the runs table
shows it in: 'f_tu', 'f_tu^2', 'f_tj*sigma_v', 'f_tj*(L + t)/(H + t)'."""
import ast
import operator

# the fewest samples the equations are fitted on: their nested 5-fold
# cross-validation over whole samples gives each inner fit 5 groups of the
# outer fold's 4/5, so at least 7 samples
MIN_SAMPLES = 7

_OPERATORS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
              ast.Pow: operator.pow, ast.USub: operator.neg, ast.UAdd: operator.pos}


def parse_term(term, inputs):
    """A regression feature: an arithmetic expression of the inputs (the
    names of ``inputs``: the study's variables and its sweep) and numbers
    with + - * / ^ and brackets: 'f_tu', 'f_tu^2', 'f_tj*sigma_v',
    'f_tj*(L + t)/(H + t)'.  Returns (its parsed form, the inputs it uses
    in order); ValueError says what is wrong."""
    try:
        tree = ast.parse(term.replace("^", "**"), mode="eval").body
    except SyntaxError:
        raise ValueError(f"{term!r} is not an arithmetic expression of the inputs (+ - * / ^ and brackets)") from None
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            if node.id not in inputs:
                raise ValueError(f"{node.id!r} in {term!r} is not an input: {', '.join(inputs)}")
            names.append((node.col_offset, node.id))
        elif isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise ValueError(f"{node.value!r} in {term!r} is not a number")
        elif not isinstance(node, (ast.BinOp, ast.UnaryOp, ast.Load, *_OPERATORS)):
            raise ValueError(f"{term!r}: only inputs, numbers, + - * / ^ and brackets")
    if not names:
        raise ValueError(f"{term!r} uses no input")
    return tree, tuple(dict.fromkeys(name for _, name in sorted(names)))


def evaluate_term(term, inputs):
    """The values of the term ``term`` (parse_term) over ``inputs`` (input ->
    values)."""
    def value(node):
        if isinstance(node, ast.Name):
            return inputs[node.id]
        if isinstance(node, ast.Constant):
            return node.value
        if isinstance(node, ast.UnaryOp):
            return _OPERATORS[type(node.op)](value(node.operand))
        return _OPERATORS[type(node.op)](value(node.left), value(node.right))
    return value(parse_term(term, inputs)[0])
