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


@schemathesis.check
def refused_only_beyond_the_schema(ctx, response, case):
    """A request the document allows is refused with 422 only for what no schema can state.

    Each operation's 422 answer lists those refusals' codes (`x-beyond-schema`, and
    `x-beyond-schema-with-profile` for a request naming a stored vehicle profile, whose kind the
    document cannot know): invalid geometry, a file's contents, figures that must agree, the
    mission planned; and `x-stated-in-words`, rules of a plan request its members' descriptions
    state because generators give up on more than eight rules in one schema. Any other 422 to a
    request
    generated as valid means a bound, a required member or a dependency missing from the
    document.
    """
    meta = case.meta
    if meta is None or not meta.generation.mode.is_positive or response.status_code != 422:
        return None
    problem = response.json()
    answer = case.operation.definition.raw.get("responses", {}).get("422", {})
    beyond = answer.get("x-beyond-schema", []) + answer.get("x-stated-in-words", [])
    if names_a_profile(case.body):
        beyond = beyond + answer.get("x-beyond-schema-with-profile", [])
    if problem.get("code") not in beyond:
        raise AssertionError(
            f"the document allows this request, but the server refused it: "
            f"{problem.get('code')} at {problem.get('pointer')}: {problem.get('detail')}"
        )
    return None


def names_a_profile(body):
    """Whether a request body names a vehicle profile anywhere (its vehicle, a fleet's drone)."""
    if isinstance(body, dict):
        return isinstance(body.get("profile"), str) or any(names_a_profile(v) for v in body.values())
    if isinstance(body, list):
        return any(names_a_profile(v) for v in body)
    return False
