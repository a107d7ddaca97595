"""The one place where errors become status-bar reports.

Operators wrap their `execute` with `@reports_errors("Importing the pattern")`: a
`tailor.TailorError` (from the module) or an `AddonError` (from the add-on's checks) is
reported as `{'ERROR'}` with what went wrong and what to do (`core.describe`), and the
operator returns `{'CANCELLED'}`. Operators compute everything before they change the scene,
so nothing the artist made is changed when this fires. Any other exception is a bug and
propagates with its traceback.
"""

from __future__ import annotations

import functools

from .core.errors import describe, is_reportable


def report(op, exc: BaseException, what: str) -> None:
    op.report({"ERROR"}, describe(exc, what))


def reports_errors(what: str):
    def wrap(execute):
        @functools.wraps(execute)
        def run(self, context):
            try:
                return execute(self, context)
            except Exception as exc:
                if not is_reportable(exc):
                    raise
                report(self, exc, what)
                return {"CANCELLED"}

        return run

    return wrap
