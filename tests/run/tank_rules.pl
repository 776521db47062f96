% `strata run` of a PROLOG mission: not supported yet (exit 64). The file
% exists so the refusal is about the kind of mission, not a missing file.
mission :- initialize, dive_from_surface, submerge_to_depth, return_to_surface.
