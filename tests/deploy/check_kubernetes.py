"""Offline checks of deploy/kubernetes/ (run by tests/run_all.sh).

- yamllint, with deploy/kubernetes/.yamllint.yaml;
- kubernetes-validate, strict, on every resource Kubernetes itself defines;
- KEDA's resources, which kubernetes-validate has no schema for: the members KEDA's
  PostgreSQL scaler reads, and that they name what the other manifests define;
- that the manifests fit each other: the pods' labels match the Service's and the
  PodDisruptionBudget's selectors, readiness is asked on /readyz, the termination grace period
  is longer than the server's own shutdown grace.

The scaler's query itself runs on the test databases in tests/it/db/deployment.rs.
"""

import pathlib
import subprocess
import sys

import kubernetes_validate
import yaml

HERE = pathlib.Path(__file__).resolve().parent
MANIFESTS = HERE.parent.parent / "deploy" / "kubernetes"
KUBERNETES_VERSION = "1.33.0"


def fail(message):
    print(f"check_kubernetes: {message}", file=sys.stderr)
    sys.exit(1)


def resources():
    for path in sorted(MANIFESTS.glob("*.yaml")):
        if path.name.startswith("."):
            continue
        for doc in yaml.safe_load_all(path.read_text()):
            if doc is not None:
                yield path.name, doc


def by_kind(docs, kind):
    return {d["metadata"]["name"]: d for _, d in docs if d["kind"] == kind}


def check_keda(docs, deployments, secrets_read):
    auths = by_kind(docs, "TriggerAuthentication")
    for name, auth in auths.items():
        refs = auth["spec"].get("secretTargetRef") or fail(f"TriggerAuthentication {name} has no secretTargetRef")
        for ref in refs:
            if set(ref) != {"parameter", "name", "key"}:
                fail(f"TriggerAuthentication {name}: a secretTargetRef has {sorted(ref)}, not parameter, name and key")
            if (ref["name"], ref["key"]) not in secrets_read:
                fail(f"TriggerAuthentication {name} reads secret {ref['name']}/{ref['key']}, which no Deployment reads")
    scaled = by_kind(docs, "ScaledObject")
    if not scaled:
        fail("no ScaledObject")
    for name, obj in scaled.items():
        spec = obj["spec"]
        target = spec.get("scaleTargetRef", {}).get("name")
        if target not in deployments:
            fail(f"ScaledObject {name} scales {target!r}, which is no Deployment here")
        if not 1 <= spec.get("minReplicaCount", 0) <= spec.get("maxReplicaCount", 100):
            fail(f"ScaledObject {name}: replica counts out of order")
        for trigger in spec["triggers"]:
            if trigger["type"] != "postgresql":
                fail(f"ScaledObject {name}: trigger {trigger['type']}, expected postgresql")
            meta = trigger["metadata"]
            unknown = set(meta) - {"query", "targetQueryValue", "activationTargetQueryValue"}
            if unknown or "query" not in meta or "targetQueryValue" not in meta:
                fail(f"ScaledObject {name}: postgresql metadata {sorted(meta)}")
            if not all(isinstance(v, str) for v in meta.values()):
                fail(f"ScaledObject {name}: KEDA's metadata values are strings")
            float(meta["targetQueryValue"])
            auth = trigger.get("authenticationRef", {}).get("name")
            if auth not in auths or not any(r["parameter"] == "connection" for r in auths[auth]["spec"]["secretTargetRef"]):
                fail(f"ScaledObject {name}: its authenticationRef {auth!r} gives no `connection`")


def check_fit(docs, deployments):
    for name, deployment in deployments.items():
        pod = deployment["spec"]["template"]
        labels = pod["metadata"]["labels"]
        for kind in ("Service", "PodDisruptionBudget"):
            for other, obj in by_kind(docs, kind).items():
                selector = obj["spec"]["selector"]
                selector = selector.get("matchLabels", selector)
                if not selector.items() <= labels.items():
                    fail(f"{kind} {other} selects {selector}, not the pods of {name} ({labels})")
        container = pod["spec"]["containers"][0]
        if container.get("readinessProbe", {}).get("httpGet", {}).get("path") != "/readyz":
            fail(f"Deployment {name}: readiness is not asked on /readyz")
        env = {e["name"]: e.get("value") for e in container.get("env", [])}
        grace = float(env.get("COVERPLAN_SHUTDOWN_GRACE_S") or 30)
        if pod["spec"].get("terminationGracePeriodSeconds", 30) <= grace:
            fail(f"Deployment {name}: the termination grace period is not longer than the server's shutdown grace ({grace} s)")


def main():
    lint = subprocess.run([sys.executable, "-m", "yamllint", "--strict", "-c", str(MANIFESTS / ".yamllint.yaml"), str(MANIFESTS)])
    if lint.returncode != 0:
        fail("yamllint found problems")
    docs = list(resources())
    for file, doc in docs:
        if doc["apiVersion"].startswith("keda.sh/"):
            continue
        try:
            kubernetes_validate.validate(doc, KUBERNETES_VERSION, strict=True)
        except kubernetes_validate.ValidationError as e:
            fail(f"{file}: {doc['kind']} {doc['metadata']['name']}: {e.message} at {list(e.path)}")
    deployments = by_kind(docs, "Deployment")
    secrets_read = {
        (e["valueFrom"]["secretKeyRef"]["name"], e["valueFrom"]["secretKeyRef"]["key"])
        for d in deployments.values()
        for c in d["spec"]["template"]["spec"]["containers"]
        for e in c.get("env", [])
        if "secretKeyRef" in e.get("valueFrom", {})
    }
    check_keda(docs, deployments, secrets_read)
    check_fit(docs, deployments)
    print(f"check_kubernetes: {len(docs)} resources ok (Kubernetes {KUBERNETES_VERSION}, strict)")


if __name__ == "__main__":
    main()
