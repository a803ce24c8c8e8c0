#include "store/db/schema.hpp"

#include <array>
#include <chrono>
#include <string_view>
#include <thread>

namespace gyrocal::db {
namespace {

// v0 -> v1. Columns carry their unit in the name; NaN is stored as NULL.
constexpr std::string_view kV1 = R"sql(
CREATE TABLE gyrocal_meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
INSERT INTO gyrocal_meta(key, value) VALUES ('application', 'gyrocal');

-- One row per calibration run; run_id '' is the "no run" bucket for what arrives outside any run.
CREATE TABLE runs (
  run_id TEXT PRIMARY KEY,
  started_utime INTEGER,          -- [us] sender clock of the start event
  stopped_utime INTEGER,          -- [us] sender clock of stop/abort; NULL while running
  outcome TEXT NOT NULL DEFAULT 'running',  -- 'running', 'stop', 'abort', 'none' (no-run bucket)
  reason TEXT NOT NULL DEFAULT '',
  software_version TEXT NOT NULL DEFAULT '',
  config_json TEXT NOT NULL DEFAULT '',
  command_line TEXT NOT NULL DEFAULT '',
  host TEXT NOT NULL DEFAULT '',
  recorder_version TEXT NOT NULL DEFAULT '',
  recorder_host TEXT NOT NULL DEFAULT '',
  first_recv_utime INTEGER        -- [us] recorder wall clock when the run was first seen
);
INSERT INTO runs(run_id, outcome, reason) VALUES ('', 'none', 'messages received outside any run');
CREATE TABLE run_sensors (run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  PRIMARY KEY (run_id, sensor_id));
CREATE TABLE sensors (sensor_id TEXT PRIMARY KEY, first_recv_utime INTEGER);

CREATE TABLE gyro_samples (
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  utime INTEGER NOT NULL, seq INTEGER NOT NULL,
  gyro_v REAL, temp_v REAL, temp_c REAL, supply_v REAL,
  has_adc INTEGER NOT NULL, gyro_counts INTEGER, temp_counts INTEGER, supply_counts INTEGER,
  recv_utime INTEGER NOT NULL     -- [us] recorder wall clock at reception (replay timing)
);
CREATE INDEX gyro_samples_run_sensor_utime ON gyro_samples(run_id, sensor_id, utime);

CREATE TABLE encoder_samples (
  run_id TEXT NOT NULL, encoder_id TEXT NOT NULL, utime INTEGER NOT NULL, seq INTEGER NOT NULL,
  counts INTEGER, counts_per_rev INTEGER, angle_deg REAL, recv_utime INTEGER NOT NULL);
CREATE INDEX encoder_samples_run_utime ON encoder_samples(run_id, utime);

CREATE TABLE chamber_states (
  run_id TEXT NOT NULL, utime INTEGER NOT NULL, seq INTEGER NOT NULL, cmd_id INTEGER,
  setpoint_c REAL, air_c REAL, at_setpoint INTEGER, fault TEXT, recv_utime INTEGER NOT NULL);
CREATE INDEX chamber_states_run_utime ON chamber_states(run_id, utime);

CREATE TABLE chamber_cmds (
  run_id TEXT NOT NULL, msg_run_id TEXT, utime INTEGER NOT NULL, cmd_id INTEGER,
  setpoint_c REAL, ramp_rate_c_per_min REAL, recv_utime INTEGER NOT NULL);
CREATE TABLE turntable_cmds (
  run_id TEXT NOT NULL, msg_run_id TEXT, utime INTEGER NOT NULL, cmd_id INTEGER,
  move_deg REAL, rate_dps REAL, accel_dps2 REAL, recv_utime INTEGER NOT NULL);

CREATE TABLE plateau_states (
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL, utime INTEGER NOT NULL, state TEXT,
  temp_c REAL, temp_slope_c_per_min REAL, temp_std_c REAL, stable_for_s REAL,
  averaging_progress REAL, last_plateau_id INTEGER, recv_utime INTEGER NOT NULL);

-- run_id of plateaus, sensitivity points and coefficient sets is the one the message carries.
CREATE TABLE plateaus (
  plateau_row_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL, plateau_id INTEGER NOT NULL,
  utime INTEGER NOT NULL, setpoint_c REAL, start_utime INTEGER, end_utime INTEGER,
  first_seq INTEGER, last_seq INTEGER, n_samples INTEGER, n_excluded_motion INTEGER,
  seq_gaps INTEGER, temp_mean_c REAL, temp_std_c REAL, temp_sem_c REAL,
  temp_slope_c_per_min REAL, gyro_mean_v REAL, gyro_std_v REAL, gyro_sem_v REAL,
  temp_v_mean REAL, supply_mean_v REAL, recv_utime INTEGER NOT NULL);
CREATE INDEX plateaus_key ON plateaus(run_id, sensor_id, plateau_id);

CREATE TABLE sensitivity_points (
  rotation_row_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL, rotation_id INTEGER NOT NULL,
  utime INTEGER NOT NULL, start_utime INTEGER, end_utime INTEGER, first_seq INTEGER,
  last_seq INTEGER, n_samples INTEGER, direction INTEGER, temp_c REAL, encoder_angle_deg REAL,
  offset_v REAL, offset_stderr_v REAL, integral_v_s REAL, sensitivity_v_per_dps REAL,
  sensitivity_stderr_v_per_dps REAL, accepted INTEGER, reject_reason TEXT,
  recv_utime INTEGER NOT NULL);
CREATE INDEX sensitivity_points_key ON sensitivity_points(run_id, sensor_id, rotation_id);

-- A coefficient set (every message is kept; the newest row per key is the one in force).
CREATE TABLE coeff_sets (
  coeff_row_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL, coeff_set_id INTEGER NOT NULL,
  source TEXT NOT NULL, utime INTEGER NOT NULL, recv_utime INTEGER NOT NULL);
CREATE INDEX coeff_sets_sensor ON coeff_sets(sensor_id, recv_utime);
-- Its two models: role 'offset' (offset_v [V]) and 'sensitivity' (sensitivity_v_per_dps).
CREATE TABLE coeff_models (
  coeff_row_id INTEGER NOT NULL, role TEXT NOT NULL, quantity TEXT, num_terms INTEGER,
  t0_c REAL, temp_min_c REAL, temp_max_c REAL, residual_rms REAL, n_points INTEGER,
  condition_number REAL, method TEXT, PRIMARY KEY (coeff_row_id, role));
CREATE TABLE coeff_terms (
  coeff_row_id INTEGER NOT NULL, role TEXT NOT NULL, term_index INTEGER NOT NULL,
  term_name TEXT NOT NULL, coeff REAL, PRIMARY KEY (coeff_row_id, role, term_index));
CREATE TABLE coeff_covariance (
  coeff_row_id INTEGER NOT NULL, role TEXT NOT NULL, row_index INTEGER NOT NULL,
  col_index INTEGER NOT NULL, value REAL, PRIMARY KEY (coeff_row_id, role, row_index, col_index));
CREATE TABLE coeff_set_plateaus (coeff_row_id INTEGER NOT NULL, plateau_id INTEGER NOT NULL);
CREATE INDEX coeff_set_plateaus_row ON coeff_set_plateaus(coeff_row_id);
CREATE TABLE coeff_set_rotations (coeff_row_id INTEGER NOT NULL, rotation_id INTEGER NOT NULL);
CREATE INDEX coeff_set_rotations_row ON coeff_set_rotations(coeff_row_id);

CREATE TABLE rates (
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL, utime INTEGER NOT NULL, seq INTEGER,
  rate_dps REAL, angle_deg REAL, temp_c REAL, coeff_set_id INTEGER, range_flag INTEGER,
  recv_utime INTEGER NOT NULL);

CREATE TABLE status (
  run_id TEXT NOT NULL, utime INTEGER NOT NULL, process TEXT, host TEXT, pid INTEGER,
  state TEXT, received INTEGER, published INTEGER, decode_errors INTEGER, seq_gaps INTEGER,
  queue_drops INTEGER, rejected INTEGER, last_reject TEXT,
  extra_json TEXT,                -- {"name": value, ...} of the process-specific counters
  recv_utime INTEGER NOT NULL);

CREATE TABLE run_events (
  run_id TEXT NOT NULL, utime INTEGER NOT NULL, event TEXT NOT NULL, reason TEXT,
  setpoint_index INTEGER, setpoint_c REAL, sensor_ids_json TEXT, software_version TEXT,
  config_json TEXT, command_line TEXT, host TEXT, recv_utime INTEGER NOT NULL);

-- Loss per run and per publisher stream (channel); channel '' = the recorder itself.
CREATE TABLE losses (
  run_id TEXT NOT NULL, channel TEXT NOT NULL,
  seq_gaps INTEGER NOT NULL DEFAULT 0,      -- [count] samples missing per seq
  seq_backwards INTEGER NOT NULL DEFAULT 0, -- [count] reordered/duplicated/restarted
  decode_errors INTEGER NOT NULL DEFAULT 0, -- [count] known fingerprint that did not decode
  queue_drops INTEGER NOT NULL DEFAULT 0,   -- [count] dropped by the recorder's bounded queue
  PRIMARY KEY (run_id, channel));

-- Messages of unknown type (or that failed to decode), undecoded.
CREATE TABLE raw_events (
  run_id TEXT NOT NULL, channel TEXT NOT NULL, recv_utime INTEGER NOT NULL,
  fingerprint TEXT NOT NULL,      -- first 8 bytes of the message, hex
  reason TEXT NOT NULL,           -- 'unknown_type' or 'decode_error'
  data BLOB);
)sql";

// v1 -> v2: recorder sessions (crash/restart visibility), views for the common questions.
constexpr std::string_view kV2 = R"sql(
CREATE TABLE recorder_sessions (
  session_id INTEGER PRIMARY KEY,
  started_wall_utime INTEGER NOT NULL, stopped_wall_utime INTEGER,  -- NULL: crashed or running
  host TEXT, pid INTEGER, recorder_version TEXT, resumed_run_id TEXT);

-- From a coefficient set to each plateau and rotation it used, with the sample range.
CREATE VIEW v_coeff_provenance AS
SELECT c.coeff_row_id, c.sensor_id, c.run_id, c.coeff_set_id, c.source, 'plateau' AS kind,
       l.plateau_id AS item_id, p.start_utime, p.end_utime, p.first_seq, p.last_seq,
       p.n_samples, (p.plateau_row_id IS NOT NULL) AS item_found
FROM coeff_sets c JOIN coeff_set_plateaus l ON l.coeff_row_id = c.coeff_row_id
LEFT JOIN plateaus p ON p.plateau_row_id = (SELECT max(plateau_row_id) FROM plateaus q
    WHERE q.run_id = c.run_id AND q.sensor_id = c.sensor_id AND q.plateau_id = l.plateau_id)
UNION ALL
SELECT c.coeff_row_id, c.sensor_id, c.run_id, c.coeff_set_id, c.source, 'rotation',
       l.rotation_id, s.start_utime, s.end_utime, s.first_seq, s.last_seq, s.n_samples,
       (s.rotation_row_id IS NOT NULL)
FROM coeff_sets c JOIN coeff_set_rotations l ON l.coeff_row_id = c.coeff_row_id
LEFT JOIN sensitivity_points s ON s.rotation_row_id = (SELECT max(rotation_row_id)
    FROM sensitivity_points q WHERE q.run_id = c.run_id AND q.sensor_id = c.sensor_id
    AND q.rotation_id = l.rotation_id);

-- ... and on to every raw gyro sample in those ranges.
CREATE VIEW v_coeff_samples AS
SELECT v.coeff_row_id, v.kind, v.item_id, g.*
FROM v_coeff_provenance v JOIN gyro_samples g
  ON g.run_id = v.run_id AND g.sensor_id = v.sensor_id
 AND g.utime BETWEEN v.start_utime AND v.end_utime;

-- The newest coefficient set of each sensor, offset and sensitivity terms side by side.
CREATE VIEW v_latest_coeffs AS
SELECT c.sensor_id, c.run_id, c.coeff_set_id, c.coeff_row_id, c.source, c.recv_utime,
  (SELECT group_concat(term_name || '=' || printf('%.10g', coeff), ' ') FROM
     (SELECT * FROM coeff_terms t WHERE t.coeff_row_id = c.coeff_row_id AND t.role = 'offset'
      ORDER BY term_index)) AS offset_terms,
  (SELECT t0_c FROM coeff_models m WHERE m.coeff_row_id = c.coeff_row_id AND m.role = 'offset')
     AS offset_t0_c,
  (SELECT group_concat(term_name || '=' || printf('%.10g', coeff), ' ') FROM
     (SELECT * FROM coeff_terms t WHERE t.coeff_row_id = c.coeff_row_id
      AND t.role = 'sensitivity' ORDER BY term_index)) AS sensitivity_terms,
  (SELECT t0_c FROM coeff_models m WHERE m.coeff_row_id = c.coeff_row_id
      AND m.role = 'sensitivity') AS sensitivity_t0_c
FROM coeff_sets c
WHERE c.coeff_row_id = (SELECT max(coeff_row_id) FROM coeff_sets d WHERE d.sensor_id = c.sensor_id);

-- One line per run: what was recorded and what was lost.
CREATE VIEW v_run_summary AS
SELECT r.run_id, r.outcome, r.started_utime, r.stopped_utime, r.software_version, r.host,
  (SELECT count(*) FROM gyro_samples g WHERE g.run_id = r.run_id) AS gyro_samples,
  (SELECT count(*) FROM plateaus p WHERE p.run_id = r.run_id) AS plateaus,
  (SELECT count(*) FROM sensitivity_points s WHERE s.run_id = r.run_id) AS sensitivity_points,
  (SELECT count(*) FROM coeff_sets c WHERE c.run_id = r.run_id) AS coeff_sets,
  (SELECT coalesce(sum(seq_gaps), 0) FROM losses l WHERE l.run_id = r.run_id) AS seq_gaps,
  (SELECT coalesce(sum(decode_errors), 0) FROM losses l WHERE l.run_id = r.run_id)
     AS decode_errors,
  (SELECT coalesce(sum(queue_drops), 0) FROM losses l WHERE l.run_id = r.run_id) AS queue_drops
FROM runs r;

CREATE INDEX status_run ON status(run_id);
CREATE INDEX run_events_run ON run_events(run_id);
CREATE INDEX rates_run_sensor ON rates(run_id, sensor_id);
)sql";

// v2 -> v3: a block index replaces the per-row index of gyro_samples (and rates).
constexpr std::string_view kV3 = R"sql(
DROP INDEX gyro_samples_run_sensor_utime;
DROP INDEX rates_run_sensor;
-- One row per committed batch and (run, sensor): where that batch put the sensor's samples.
-- Ranges of one (run, sensor) never overlap; other sensors' rows may lie inside a range.
CREATE TABLE gyro_blocks (
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  first_rowid INTEGER NOT NULL, last_rowid INTEGER NOT NULL,  -- gyro_samples.rowid range
  min_utime INTEGER NOT NULL, max_utime INTEGER NOT NULL,      -- [us] utime range of its samples
  n_samples INTEGER NOT NULL);                                 -- [count] its samples in the range
CREATE INDEX gyro_blocks_key ON gyro_blocks(run_id, sensor_id, max_utime);
INSERT INTO gyro_blocks SELECT run_id, sensor_id, min(rowid), max(rowid), min(utime), max(utime),
  count(*) FROM gyro_samples GROUP BY run_id, sensor_id;

DROP VIEW v_coeff_samples;
CREATE VIEW v_coeff_samples AS
SELECT v.coeff_row_id, v.kind, v.item_id, g.*
FROM v_coeff_provenance v
JOIN gyro_blocks b ON b.run_id = v.run_id AND b.sensor_id = v.sensor_id
 AND b.max_utime >= v.start_utime AND b.min_utime <= v.end_utime
JOIN gyro_samples g ON g.rowid BETWEEN b.first_rowid AND b.last_rowid
 AND g.run_id = v.run_id AND g.sensor_id = v.sensor_id
 AND g.utime BETWEEN v.start_utime AND v.end_utime;

DROP VIEW v_run_summary;
CREATE VIEW v_run_summary AS
SELECT r.run_id, r.outcome, r.started_utime, r.stopped_utime, r.software_version, r.host,
  (SELECT coalesce(sum(n_samples), 0) FROM gyro_blocks b WHERE b.run_id = r.run_id) AS gyro_samples,
  (SELECT count(*) FROM plateaus p WHERE p.run_id = r.run_id) AS plateaus,
  (SELECT count(*) FROM sensitivity_points s WHERE s.run_id = r.run_id) AS sensitivity_points,
  (SELECT count(*) FROM coeff_sets c WHERE c.run_id = r.run_id) AS coeff_sets,
  (SELECT coalesce(sum(seq_gaps), 0) FROM losses l WHERE l.run_id = r.run_id) AS seq_gaps,
  (SELECT coalesce(sum(decode_errors), 0) FROM losses l WHERE l.run_id = r.run_id)
     AS decode_errors,
  (SELECT coalesce(sum(queue_drops), 0) FROM losses l WHERE l.run_id = r.run_id) AS queue_drops
FROM runs r;
)sql";

// v3 -> v4: closed-loop analyses stored with their run; a coefficient set is kept once per
// (run, sensor, coeff_set_id, source) (the index makes the writer's existence check a seek).
// No rates(run_id, sensor_id, utime) index: it costs the recorder a large share of its insert
// rate on its gyro + rate mix (measured: store/db/README.md#schema-versions-pragma-user_version).
constexpr std::string_view kV4 = R"sql(
CREATE TABLE analyses (
  analysis_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL,               -- the analysed run
  sensor_id TEXT NOT NULL,
  created_wall_utime INTEGER NOT NULL,  -- [us] wall clock when the analysis was stored
  software_version TEXT NOT NULL DEFAULT '',
  command_line TEXT NOT NULL DEFAULT '',
  verdict TEXT NOT NULL DEFAULT '',   -- e.g. 'no missing effect', 'added temp_rate', 'ambiguous'
  candidates_json TEXT NOT NULL DEFAULT '[]',  -- [{effect, statistic, decision, ...}]: what was tested
  added_json TEXT NOT NULL DEFAULT '[]',       -- [{effect, term, coefficient, stderr, unit}]: what was added
  offset_rms_v_before REAL, offset_rms_v_after REAL,   -- [V] residual RMS, declared / extended model
  rate_rms_dps_before REAL, rate_rms_dps_after REAL,   -- [deg/s]
  drift_dph_before REAL, drift_dph_after REAL,         -- [deg/h] integrated drift, held-out stretch
  floor_rate_rms_dps REAL,            -- [deg/s] noise floor the data allows (scatter in plateaus)
  result_json TEXT NOT NULL DEFAULT '',  -- the analysis' whole JSON result for this sensor
  coeff_row_id INTEGER                -- coeff_sets row of the extended model (source
                                      -- 'analysis:<analysis_id>'); NULL when none was stored
);
CREATE INDEX analyses_run ON analyses(run_id, sensor_id);

-- One line per analysis, with the coefficient set it produced (if any).
CREATE VIEW v_analyses AS
SELECT a.analysis_id, a.run_id, a.sensor_id, a.created_wall_utime,
  datetime(a.created_wall_utime / 1000000, 'unixepoch') AS created_utc, a.verdict,
  (SELECT group_concat(json_extract(e.value, '$.effect'), ',') FROM json_each(
     CASE WHEN json_valid(a.added_json) THEN a.added_json ELSE '[]' END) e) AS added_effects,
  a.offset_rms_v_before, a.offset_rms_v_after, a.rate_rms_dps_before, a.rate_rms_dps_after,
  a.drift_dph_before, a.drift_dph_after, a.floor_rate_rms_dps, a.coeff_row_id,
  c.coeff_set_id, c.source, a.software_version, a.command_line
FROM analyses a LEFT JOIN coeff_sets c ON c.coeff_row_id = a.coeff_row_id;

CREATE INDEX coeff_sets_key ON coeff_sets(run_id, sensor_id, coeff_set_id, source);
)sql";

// v4 -> v5: when each unit was powered (POWER_<id>: the origin of time since power-on for
// warm-up terms), and validations (a stored model applied to another run of the same unit).
constexpr std::string_view kV5 = R"sql(
CREATE TABLE power_states (
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  utime INTEGER NOT NULL,           -- [us] producer clock when sent
  seq INTEGER NOT NULL,
  power_on_utime INTEGER NOT NULL,  -- [us] producer clock at which the unit was powered on
  source TEXT NOT NULL DEFAULT '',  -- how it is known: 'rig', 'csv time_since_power_s', ...
  recv_utime INTEGER NOT NULL);
CREATE INDEX power_states_run_sensor ON power_states(run_id, sensor_id, utime);

CREATE TABLE validations (
  validation_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL,              -- the run the model was applied to
  sensor_id TEXT NOT NULL,
  created_wall_utime INTEGER NOT NULL,  -- [us] wall clock when stored
  software_version TEXT NOT NULL DEFAULT '',
  command_line TEXT NOT NULL DEFAULT '',
  model_origin TEXT NOT NULL DEFAULT '',  -- where the model came from (database row, run, file)
  coeff_row_id INTEGER,              -- coeff_sets row of the model when it came from this database
  model_run_id TEXT,                 -- run the model was fitted on, when known
  n_bins INTEGER,                    -- still bins compared
  offset_rms_v REAL,                 -- [V] RMS of the bins' offset error
  rate_rms_dps REAL,                 -- [deg/s] the same as a rate
  drift_dph REAL,                    -- [deg/h] integrated error over the still stretches
  floor_rate_rms_dps REAL,           -- [deg/s] white noise of the bins (successive differences)
  power_on TEXT NOT NULL DEFAULT '', -- where time since power-on came from
  result_json TEXT NOT NULL DEFAULT ''
);
CREATE INDEX validations_run ON validations(run_id, sensor_id);
)sql";

// v5 -> v6: the fitter's reports on its coefficient sets (complete or partial and why, points
// excluded, the slow noise used and its source, repeatability at revisited temperatures) and the
// units' noise estimates (Allan deviation of the run's still stretches), with views.
constexpr std::string_view kV6 = R"sql(
CREATE TABLE noise_estimates (
  noise_row_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  utime INTEGER NOT NULL,             -- [us] newest sample included
  still_s REAL,                       -- [s] still, thermally quiet data used
  n_segments INTEGER, longest_segment_s REAL, tau0_s REAL,
  arw_v_rthz REAL, arw_stderr_v_rthz REAL,                -- [V/sqrt(Hz)] angle random walk N
  bias_instability_v REAL, bias_instability_stderr_v REAL, -- [V] flat Allan level B
  rrw_v_rts REAL, rrw_stderr_v_rts REAL,                  -- [V/sqrt(s)] rate random walk K
  fit_note TEXT, recv_utime INTEGER NOT NULL);
CREATE INDEX noise_estimates_key ON noise_estimates(run_id, sensor_id, utime);
CREATE TABLE noise_adev (
  noise_row_id INTEGER NOT NULL, tau_s REAL NOT NULL,     -- [s]
  adev_v REAL, adev_lo_v REAL, adev_hi_v REAL,            -- [V] and its 68 % interval
  edf REAL);
CREATE INDEX noise_adev_row ON noise_adev(noise_row_id);

CREATE TABLE fit_reports (
  fit_report_row_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  coeff_set_id INTEGER NOT NULL,      -- [us] the coefficient set described; -1 when none
  source TEXT NOT NULL, utime INTEGER NOT NULL,
  is_final INTEGER NOT NULL,          -- 1: made by the run's stop
  status TEXT NOT NULL,               -- 'complete', 'partial', 'none'
  reason TEXT NOT NULL DEFAULT '',    -- why partial or none
  offset_detail TEXT, sensitivity_detail TEXT,
  slow_noise_v REAL, slow_noise_dps REAL,  -- [V], [deg/s] added to each plateau's error
  slow_noise_source TEXT,
  recv_utime INTEGER NOT NULL);
CREATE INDEX fit_reports_key ON fit_reports(run_id, sensor_id, coeff_set_id, source);
CREATE TABLE fit_exclusions (
  fit_report_row_id INTEGER NOT NULL,
  kind TEXT NOT NULL,                 -- 'plateau' or 'rotation'
  item_id INTEGER NOT NULL,           -- plateau_id or rotation_id
  temp_c REAL, value REAL,            -- [degC], [V or V/(deg/s)]
  residual REAL, residual_sigma REAL, -- [unit of value] against the other points' prediction
  statistic REAL, threshold REAL,     -- [1] studentised deleted residual and its limit
  reason TEXT);
CREATE INDEX fit_exclusions_row ON fit_exclusions(fit_report_row_id);
CREATE TABLE repeatability (
  fit_report_row_id INTEGER NOT NULL, run_id TEXT NOT NULL, sensor_id TEXT NOT NULL,
  temp_c REAL,                        -- [degC] mean of the two visits
  first_plateau_id INTEGER, second_plateau_id INTEGER, first_temp_c REAL, second_temp_c REAL,
  first_approach INTEGER, second_approach INTEGER,  -- +1 from colder, -1 from hotter, 0 start
  offset_diff_v REAL, offset_diff_stderr_v REAL,    -- [V] second - first, model step removed
  offset_diff_dps REAL, offset_diff_stderr_dps REAL,-- [deg/s]
  z REAL, verdict TEXT);
CREATE INDEX repeatability_row ON repeatability(fit_report_row_id);

-- The final report of each run, sensor and source (the one the run's stop made, else the
-- newest), with its exclusions listed.
CREATE VIEW v_fit_final AS
SELECT f.*, (SELECT group_concat(e.kind || ' ' || e.item_id, ', ') FROM fit_exclusions e
             WHERE e.fit_report_row_id = f.fit_report_row_id) AS excluded
FROM fit_reports f
WHERE f.fit_report_row_id = (SELECT g.fit_report_row_id FROM fit_reports g
    WHERE g.run_id = f.run_id AND g.sensor_id = f.sensor_id AND g.source = f.source
    ORDER BY g.is_final DESC, g.fit_report_row_id DESC LIMIT 1);

-- Repeatability as the final reports have it.
CREATE VIEW v_repeatability AS
SELECT r.* FROM repeatability r JOIN v_fit_final f ON f.fit_report_row_id = r.fit_report_row_id;

-- The newest noise estimate of each run and sensor, also in deg/s through the sensitivity at T0
-- (term '1') of the run's newest fitter set of that sensor.
CREATE VIEW v_noise AS
SELECT n.*, s.coeff AS sensitivity_v_per_dps,
  n.arw_v_rthz / s.coeff AS arw_dps_rthz, n.arw_stderr_v_rthz / s.coeff AS arw_stderr_dps_rthz,
  n.bias_instability_v / s.coeff AS bias_instability_dps,
  n.bias_instability_stderr_v / s.coeff AS bias_instability_stderr_dps,
  n.rrw_v_rts / s.coeff AS rrw_dps_rts, n.rrw_stderr_v_rts / s.coeff AS rrw_stderr_dps_rts
FROM noise_estimates n
LEFT JOIN coeff_terms s ON s.role = 'sensitivity' AND s.term_name = '1'
  AND s.coeff_row_id = (SELECT max(c.coeff_row_id) FROM coeff_sets c
      WHERE c.run_id = n.run_id AND c.sensor_id = n.sensor_id AND c.source = 'fitter')
WHERE n.noise_row_id = (SELECT max(m.noise_row_id) FROM noise_estimates m
    WHERE m.run_id = n.run_id AND m.sensor_id = n.sensor_id);
)sql";

// v6 -> v7: a name fixed so that every column carries its unit last, like its neighbours
// gyro_mean_v and supply_mean_v (plateau_t's field was renamed with it). SQLite rewrites the views
// that name the column.
constexpr std::string_view kV7 = R"sql(
ALTER TABLE plateaus RENAME COLUMN temp_v_mean TO temp_mean_v;
)sql";

// v7 -> v8: the analysis' outcome as a column (adequate, explained, partly explained,
// unexplained residual, not testable), so acceptance reads the outcome and not the headline's
// wording; backfilled from result_json's "outcome" where an older analysis stored one (NULL
// otherwise: those analyses predate outcomes). v_analyses shows it.
constexpr std::string_view kV8 = R"sql(
ALTER TABLE analyses ADD COLUMN outcome TEXT;  -- NULL: stored before outcomes existed
UPDATE analyses SET outcome = json_extract(result_json, '$.outcome')
  WHERE json_valid(result_json) AND json_type(result_json, '$.outcome') = 'text';

DROP VIEW v_analyses;
CREATE VIEW v_analyses AS
SELECT a.analysis_id, a.run_id, a.sensor_id, a.created_wall_utime,
  datetime(a.created_wall_utime / 1000000, 'unixepoch') AS created_utc, a.outcome, a.verdict,
  (SELECT group_concat(json_extract(e.value, '$.effect'), ',') FROM json_each(
     CASE WHEN json_valid(a.added_json) THEN a.added_json ELSE '[]' END) e) AS added_effects,
  a.offset_rms_v_before, a.offset_rms_v_after, a.rate_rms_dps_before, a.rate_rms_dps_after,
  a.drift_dph_before, a.drift_dph_after, a.floor_rate_rms_dps, a.coeff_row_id,
  c.coeff_set_id, c.source, a.software_version, a.command_line
FROM analyses a LEFT JOIN coeff_sets c ON c.coeff_row_id = a.coeff_row_id;
)sql";

// v8 -> v9: a lab's central database (store/db/central_db.hpp). A station records each push of a
// run in `pushes` (so that `gyrocal push` with no run knows what is new); the centre records in
// `run_origins` where each run came from and the run_key its rows' ids are offset by. Both tables
// are in every database (the central schema is this one): each side fills its own.
constexpr std::string_view kV9 = R"sql(
CREATE TABLE pushes (
  push_id INTEGER PRIMARY KEY,
  run_id TEXT NOT NULL,
  central TEXT NOT NULL,              -- the central database's URL, without credentials
  pushed_wall_utime INTEGER NOT NULL, -- [us] wall clock when the centre committed
  run_outcome TEXT NOT NULL,          -- the run's outcome then ('running': pushed while open)
  run_mark TEXT NOT NULL,             -- what the run held then (outcome, newest ids); a run
                                      -- whose mark changed since has something new to push
  rows_added INTEGER NOT NULL,        -- [count] rows this push added at the centre
  rows_updated INTEGER NOT NULL);     -- [count] rows it changed there (runs, losses of an open run)
CREATE INDEX pushes_run ON pushes(central, run_id);

CREATE TABLE run_origins (
  run_key INTEGER PRIMARY KEY,        -- the run's number at the centre: each of its rows' ids is
                                      -- run_key * 10^12 + the station's row id
  run_id TEXT NOT NULL UNIQUE,
  station_host TEXT NOT NULL,         -- host name of the station that pushed it
  station_db TEXT NOT NULL,           -- the station's database file (absolute path)
  station_software_version TEXT NOT NULL,
  station_schema_version INTEGER NOT NULL,
  first_pushed_wall_utime INTEGER NOT NULL);  -- [us] wall clock of its first push
)sql";

constexpr std::array<std::string_view, kSchemaVersion> kSteps = {kV1, kV2, kV3, kV4, kV5,
                                                                 kV6, kV7, kV8, kV9};

bool IsGyrocalDb(Db& db) {
    Stmt s(db, "SELECT count(*) FROM sqlite_master WHERE name = 'gyrocal_meta'");
    s.Step();
    return s.Int(0) == 1;
}

bool IsEmpty(Db& db) {
    Stmt s(db, "SELECT count(*) FROM sqlite_master");
    s.Step();
    return s.Int(0) == 0;
}

// What a file holds, read in one snapshot: another process creating the same file at that
// moment commits its first schema step between two separate reads, so the version would be read
// as 0 before that commit and the tables after it, which looks like a foreign SQLite file.
struct FileState {
    int version = 0;
    bool empty = true;
    bool gyrocal = false;
};

FileState ReadFileState(Db& db) {
    db.Exec("BEGIN");  // deferred: a read transaction, whose snapshot starts at the first read
    try {
        FileState s;
        s.version = db.UserVersion();
        s.empty = IsEmpty(db);
        s.gyrocal = IsGyrocalDb(db);
        db.Exec("COMMIT");
        return s;
    } catch (...) {
        try {
            db.Exec("ROLLBACK");
        } catch (const StoreError&) {  // the read's own error is the one to report
        }
        throw;
    }
}

}  // namespace

std::string_view SchemaStep(int from_version) {
    if (from_version < 0 || from_version >= kSchemaVersion) {
        throw StoreError("no schema step from version " + std::to_string(from_version));
    }
    return kSteps[static_cast<size_t>(from_version)];
}

void ConfigureConnection(Db& db) {
    // A new file's switch to WAL needs an exclusive lock, and SQLite returns "locked" at once
    // (without its busy handler) while another process makes the same switch: two recorders
    // creating one database together. Waited out here, for as long as the busy timeout waits.
    constexpr auto kWalWait = std::chrono::seconds(5);
    const auto give_up = std::chrono::steady_clock::now() + kWalWait;
    for (;;) {
        try {
            db.Exec("PRAGMA journal_mode = WAL");
            break;
        } catch (const StoreError& e) {
            const int primary = e.sqlite_code() & 0xff;
            const bool locked = primary == SQLITE_BUSY || primary == SQLITE_LOCKED;
            if (!locked || std::chrono::steady_clock::now() >= give_up) throw;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    db.Exec("PRAGMA synchronous = NORMAL");
    db.Exec("PRAGMA foreign_keys = OFF");
}

void Migrate(Db& db, int target_version) {
    if (target_version < 0 || target_version > kSchemaVersion) {
        throw StoreError("schema version " + std::to_string(target_version) + " is not valid (0.." +
                         std::to_string(kSchemaVersion) + ")");
    }
    const FileState state = ReadFileState(db);
    int version = state.version;
    if (version > kSchemaVersion) {
        throw StoreError("database '" + db.path() + "' has schema version " +
                         std::to_string(version) + ", newer than this software (" +
                         std::to_string(kSchemaVersion) + "): use a newer gyrocal");
    }
    if (version == 0 && !state.empty) {
        throw StoreError("'" + db.path() + "' is an SQLite file but not a gyrocal database");
    }
    if (version > 0 && !state.gyrocal) {
        throw StoreError("'" + db.path() + "' is not a gyrocal database (no gyrocal_meta table)");
    }
    while (version < target_version) {
        Transaction tx(db);
        // Another process may have migrated the file while this one waited for the write lock
        // (two chambers' recorders creating one database at once): go on from what it says now.
        if (const int now = db.UserVersion(); now != version) {
            version = now;
            continue;
        }
        db.Exec(kSteps[static_cast<size_t>(version)]);
        db.SetUserVersion(version + 1);
        tx.Commit();
        ++version;
    }
}

}  // namespace gyrocal::db
