//! Every integration test of `celltissue` in one binary: each file under `tests/` is a module
//! (named after what it validates), and `common` holds the helpers some of them share. Run one
//! file's tests with `cargo test --release --test integration <file>::`.

mod common;

mod accuracy_contract;
mod array_data;
mod cli_catalogue;
mod cli_errors;
mod cli_run;
mod division_cap;
mod division_jacobian_map;
mod division_restart;
mod division_thesis;
mod division_viscous_cells;
mod docs_snippets_parse;
mod energy_checks;
mod energy_closed_forms;
mod energy_expression_fig2_5;
mod energy_serde;
mod ensemble_statistics;
mod external_pressure;
mod growth_newton_matrix_condenses;
mod growth_proliferating_continuum;
mod growth_thesis;
mod line_active_ring;
mod line_discrete_continuum_convergence;
mod line_field_edits;
mod line_growth_without_division;
mod line_invariants;
mod line_jacobian;
mod line_raw_thesis_large_n;
mod line_small_k_exponential_ramp;
mod line_static_equilibrium;
mod line_structure;
mod line_table_2_1;
mod line_uniform_polynomial_ramp;
mod locking_energies;
mod maxwell_sls;
mod methods_on_cell_models;
mod mode_tethered_line;
#[cfg(feature = "hdf5")]
mod output_hdf5;
mod output_integrity;
mod plots;
mod proliferation_batched_divisions;
mod proliferation_cell_grid;
mod proliferation_division_cost;
mod proliferation_division_rules;
mod proliferation_fig3_3_claims;
mod proliferation_rim_speed;
mod proliferation_ring;
mod roundoff_floor;
mod scenario_fuzz;
mod scenario_outputs;
mod scenario_validation;
mod shear_validation;
mod sheet_external_pressure;
mod sheet_growth;
mod sheet_kelvin_voigt;
mod sheet_output;
mod sheet_structure;
mod sheet_validation;
mod sheet_viscoelasticity;
mod sweep_jobs_and_shards;
mod thesis_panels;
mod time_scale_invariance;
