-- 0013_registrations_datum: every series point carries its epoch's datum (the registration
-- method) and whether that registration was accepted (docs/schema.md, "registrations"). A
-- registration row is large (its quality report as JSON: 7.5 MB for a year of 15-minute
-- epochs), so reading those two columns through the table reads every page of it; this
-- covering index holds just them (about 1 MB a year), and the series query names it.
CREATE INDEX registrations_datum ON registrations (epoch_id, method, accepted);
