"""schemathesis's command line, with a workaround for a CPython 3.11 bug.

hypothesis describes a filtered strategy by parsing the source of its lambda; on CPython 3.11
that parse can fail with "SystemError: AST constructor recursion depth mismatch" when it runs
deep in the stack, which schemathesis then reports as an error of the operation under test. The
description only names the strategy in messages, so a failed one becomes "lambda".
"""

import sys

from hypothesis.internal import lambda_sources

_describe = lambda_sources.lambda_description


def _described(f):
    try:
        return _describe(f)
    except SystemError:
        return "lambda"


lambda_sources.lambda_description = _described

from schemathesis.cli import schemathesis  # noqa: E402  (after the workaround)

if __name__ == "__main__":
    sys.argv[0] = "schemathesis"
    sys.exit(schemathesis())
