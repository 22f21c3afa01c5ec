"""The examples in the type stubs' docstrings run and print what they show."""

import ast
import doctest
import os

import volsample

STUBS = os.path.join(os.path.dirname(volsample.__file__), "_volsample.pyi")


def test_stub_examples():
    if not os.path.exists(STUBS):  # an installed wheel without the stub next to the package
        import pytest
        pytest.skip("stubs not installed")
    tree = ast.parse(open(STUBS, encoding="utf-8").read())
    docs = [ast.get_docstring(n) for n in ast.walk(tree)
            if isinstance(n, (ast.FunctionDef, ast.ClassDef, ast.Module))]
    parser = doctest.DocTestParser()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    examples = 0
    for i, doc in enumerate(d for d in docs if d):
        test = parser.get_doctest(doc, dict(vars(volsample)), f"stub docstring {i}", STUBS, 0)
        examples += len(test.examples)
        runner.run(test)
    assert examples >= 8
    assert runner.summarize(verbose=False).failed == 0
