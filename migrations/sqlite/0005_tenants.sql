-- API keys and tenants. A key is `cpk_<id>_<secret>`; only the SHA-256 of the secret is kept.
-- Once any key exists (revoked ones included) every API request needs one.
CREATE TABLE api_keys (
    id          TEXT PRIMARY KEY NOT NULL,
    tenant      TEXT NOT NULL,
    admin       INTEGER NOT NULL DEFAULT 0,
    secret_hash TEXT NOT NULL,
    created_at  TEXT NOT NULL,
    revoked_at  TEXT
);

-- what each tenant owns; rows made before tenants belong to `default`, the open server's tenant
ALTER TABLE missions ADD COLUMN tenant TEXT NOT NULL DEFAULT 'default';
CREATE INDEX missions_tenant ON missions (tenant, created_at);
ALTER TABLE plans ADD COLUMN tenant TEXT NOT NULL DEFAULT 'default';
CREATE INDEX plans_tenant_status ON plans (tenant, status);

-- vehicle profiles are keyed by tenant and id; the built-ins belong to no tenant ('')
CREATE TABLE vehicles_by_tenant (
    tenant      TEXT NOT NULL,
    id          TEXT NOT NULL,
    builtin     INTEGER NOT NULL DEFAULT 0,
    body        TEXT NOT NULL,
    created_at  TEXT NOT NULL,
    updated_at  TEXT NOT NULL,
    PRIMARY KEY (tenant, id)
);
INSERT INTO vehicles_by_tenant (tenant, id, builtin, body, created_at, updated_at)
    SELECT CASE WHEN builtin = 1 THEN '' ELSE 'default' END, id, builtin, body, created_at, updated_at FROM vehicles;
DROP TABLE vehicles;
ALTER TABLE vehicles_by_tenant RENAME TO vehicles;
