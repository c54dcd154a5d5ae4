"""schemathesis hooks for tests/fuzz/fuzz_api.py.

A client sends a fresh Idempotency-Key with each new request and the same key only with a retry
of it. Generated keys repeat (hypothesis likes short strings such as "0"), which would make
unrelated requests replays of each other's first answers; every request gets a key of its own
here. Replays are tested in tests/it/api.rs.
"""

import uuid

import schemathesis


@schemathesis.hook
def before_call(context, case, kwargs):
    # negative cases are left as generated: editing them makes schemathesis treat them as
    # positive and send headers they meant to leave out
    if case.meta is not None and case.meta.generation.mode.is_negative:
        return
    headers = case.headers or {}
    for name in list(headers):
        if name.lower() == "idempotency-key":
            headers[name] = str(uuid.uuid4())
