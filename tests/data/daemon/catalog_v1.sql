-- Catalog fixture at schema version 1 (garmcapd 0.1), as written by that version: used by
-- tests/daemon/catalog_test.cpp to check the migration to the current schema.
PRAGMA application_id = 1195589968;
PRAGMA user_version = 1;
CREATE TABLE images(
  sha256 TEXT PRIMARY KEY CHECK(length(sha256) = 64),
  media_type TEXT NOT NULL,
  bytes INTEGER NOT NULL,
  created_at TEXT NOT NULL);
CREATE TABLE calibrations(
  id INTEGER PRIMARY KEY,
  created_at TEXT NOT NULL,
  empty_sha256 TEXT NOT NULL REFERENCES images(sha256),
  json TEXT NOT NULL);
CREATE TABLE jobs(
  id INTEGER PRIMARY KEY,
  kind TEXT NOT NULL,
  state TEXT NOT NULL CHECK(state IN ('queued','running','done','failed')),
  stage TEXT NOT NULL DEFAULT '',
  progress REAL NOT NULL DEFAULT 0,
  item_id INTEGER,
  calibration_id INTEGER REFERENCES calibrations(id),
  error TEXT NOT NULL DEFAULT '',
  created_at TEXT NOT NULL,
  updated_at TEXT NOT NULL);
CREATE TABLE items(
  id INTEGER PRIMARY KEY,
  sku TEXT NOT NULL DEFAULT '',
  title TEXT NOT NULL DEFAULT '',
  price_cents INTEGER,
  tags TEXT NOT NULL DEFAULT '[]',
  notes TEXT NOT NULL DEFAULT '',
  status TEXT NOT NULL DEFAULT 'draft',
  type TEXT NOT NULL DEFAULT '',
  attributes TEXT NOT NULL DEFAULT '{}',
  confidence REAL NOT NULL DEFAULT 0,
  calibration_id INTEGER REFERENCES calibrations(id),
  job_id INTEGER REFERENCES jobs(id),
  created_at TEXT NOT NULL,
  updated_at TEXT NOT NULL,
  deleted_at TEXT);
CREATE TABLE measurements(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  value_cm REAL NOT NULL,
  PRIMARY KEY(item_id, name));
CREATE TABLE item_images(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  kind TEXT NOT NULL,
  sha256 TEXT NOT NULL REFERENCES images(sha256),
  PRIMARY KEY(item_id, kind));
CREATE TABLE patterns(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  size TEXT NOT NULL,
  json TEXT NOT NULL,
  PRIMARY KEY(item_id, size));
CREATE INDEX items_sku ON items(sku);
INSERT INTO images VALUES('aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa','image/png',10,'2026-01-01T00:00:00.000Z');
INSERT INTO calibrations VALUES(1,'2026-01-01T00:00:00.000Z','aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa','{"scale_px_per_cm": 10}');
INSERT INTO jobs VALUES(1,'dressed','done','done',1,1,1,'','2026-01-01T00:00:00.000Z','2026-01-01T00:00:01.000Z');
INSERT INTO items VALUES(1,'SKU-1','Blue skirt',2500,'["summer"]','','active','skirt','{"skirt":"a_line"}',0.93,1,1,'2026-01-01T00:00:01.000Z','2026-01-01T00:00:01.000Z',NULL);
INSERT INTO items VALUES(2,'SKU-2','Grey top',NULL,'[]','check sleeves','draft','top','{}',0.41,1,NULL,'2026-01-01T00:00:02.000Z','2026-01-01T00:00:02.000Z',NULL);
INSERT INTO measurements VALUES(1,'waist_circ',68.5);
INSERT INTO measurements VALUES(1,'hip_circ',94.0);
INSERT INTO item_images VALUES(1,'dressed','aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa');
INSERT INTO patterns VALUES(1,'base','{"type":"skirt"}');
