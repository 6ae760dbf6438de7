//! Offline solver for the initial costate of the Purcell swimmer, and replay through the core.
