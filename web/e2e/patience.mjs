// How long the browser tests wait before they call something missing: the
// limits written in them (a click, a state polled for, a server's first
// line) times PATIENCE, 4 unless STRATA_E2E_PATIENCE says otherwise. The
// limits only end a test whose studio is broken; a busy machine (an ASan
// build beside the tests, a load of 10) must never reach them, and once
// did at 15 s (a click on the file list).
export const PATIENCE = Math.max(1, Number(process.env.STRATA_E2E_PATIENCE) || 4);

// ms, as written in a test, made patient.
export const patient = (ms) => ms * PATIENCE;
