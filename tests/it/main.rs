//! The integration tests: one binary (ripgrep's layout), run by
//! libtest-mimic so that a test whose outside tool or data is absent
//! (`tclsh`, POV-Ray, netpbm, GNU parallel, `script`, `../shared/models`)
//! shows as ignored, with its reason, in the summary, never as passed.
//! Every test is a `pub fn NAME()` in its module, listed below
//! (`tidy::every_test_is_registered` checks the list).

mod bad;
mod cli;
mod farm;
mod interrupt;
mod lang;
mod mesh;
mod path;
mod pov;
mod readme;
mod render;
mod safe;
mod sampling;
mod shapes;
mod surfaces;
mod tidy;
mod util;

use libtest_mimic::{Arguments, Completion, Failed, Trial};

/// Runs one test: a panic is a failure, `util::skip` an ignore with its
/// reason.
fn trial(name: &'static str, test: fn()) -> Trial {
    Trial::ignorable_test(name, move || match std::panic::catch_unwind(test) {
        Ok(()) => Ok(Completion::Completed),
        Err(payload) => match payload.downcast::<util::Skip>() {
            Ok(skip) => Ok(Completion::ignored_with(skip.0)),
            Err(payload) => Err(Failed::from(panic_message(&payload))),
        },
    })
}

fn panic_message(payload: &Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panicked".into()
    }
}

macro_rules! tests {
    ($($path:path),* $(,)?) => {
        vec![$(trial(stringify!($path), $path)),*]
    };
}

fn main() {
    // A skip is a panic with a `Skip` payload: not worth a backtrace.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if info.payload().downcast_ref::<util::Skip>().is_none() {
            default_hook(info);
        }
    }));
    let args = Arguments::from_args();
    let trials = tests![
        path::a_diffuse_ball_in_a_white_furnace_shows_its_albedo,
        path::a_diffuse_ball_under_half_a_sky_shows_its_tilt,
        path::a_glowing_closed_box_sums_its_bounces,
        path::agrees_with_mitsuba_on_the_cornell_box,
        path::path_traced_pictures_do_not_depend_on_threads_passes_or_crops,
        path::noise_targets_trade_rays_for_error,
        path::bad_path_commands_are_located_errors,
        sampling::edges_converge_to_their_covered_fractions,
        sampling::sampled_pictures_do_not_depend_on_threads_passes_or_crops,
        sampling::seeds_change_the_noise_only,
        sampling::exposure_and_tone_maps_follow_their_formulas,
        sampling::sampling_commands_refuse_bad_values,
        sampling::depth_of_field_blurs_into_the_circle_of_confusion,
        sampling::adaptive_sampling_spends_fewer_samples_for_the_same_error,
        sampling::agrees_with_mitsuba_on_lambert_scenes,
        sampling::area_and_sphere_lights_match_their_form_factors,
        sampling::motion_blur_streaks_by_velocity_times_shutter,
        sampling::moving_objects_are_where_the_shutter_says,
        sampling::penumbrae_match_similar_triangles,
        shapes::transformed_objects_match_objects_built_in_place,
        shapes::ellipsoids_shade_by_their_gradient,
        shapes::instances_render_as_copies,
        shapes::csg_follows_the_boolean_formula,
        shapes::bad_structure_is_a_located_error,
        shapes::spd_scenes_load_with_their_counts,
        shapes::sphereflakes_match_their_spheres,
        shapes::sponges_match_their_boxes,
        shapes::blobs_and_closed_meshes_join_csg,
        surfaces::checkers_follow_their_parity_and_their_object,
        surfaces::bumps_shade_by_the_perturbed_normal,
        surfaces::blinn_and_ward_highlights_follow_their_formulas,
        surfaces::bad_surfaces_are_located_errors,
        surfaces::image_textures_put_texels_where_their_projection_says,
        surfaces::uv_textures_follow_the_mesh_coordinates,
        surfaces::textures_tint_light_through_glass,
        surfaces::mip_maps_keep_far_textures_close_to_supersampled,
        surfaces::displacement_changes_bounds_and_silhouettes,
        surfaces::image_bumps_and_displacements_follow_the_image,
        bad::the_corpus_is_big_enough,
        bad::every_bad_input_exits_with_a_located_message,
        bad::the_repl_survives_every_bad_input,
        bad::the_repl_keeps_its_session_past_the_memory_budget,
        bad::hostile_renders_finish_under_a_memory_cap,
        bad::picture_headers_are_checked_before_decoding,
        bad::the_budget_is_a_ceiling_for_peak_memory,
        safe::every_fence_holds,
        safe::every_path_command_asks_the_gate,
        safe::links_lead_nowhere_outside,
        safe::outputs_environment_and_fifos_are_fenced,
        cli::dash_c_and_stdin,
        cli::argv_like_tclsh,
        cli::options,
        cli::help_lists_commands,
        cli::no_panic_on_garbage,
        cli::regressions_do_not_crash,
        cli::source_returns_the_last_result,
        cli::numbers_as_old_converters_write_them,
        cli::errors_at_the_final_render_name_the_script,
        cli::the_first_run_says_what_happened,
        cli::stdin_dash_and_dash_c_with_an_output,
        cli::the_output_is_checked_before_the_script_runs,
        cli::the_repl_leaves_error_info_as_tclsh_does,
        cli::show_draws_the_last_render_in_half_blocks,
        cli::a_bar_asked_for_is_drawn_into_a_pipe,
        cli::repl_stats_leave_out_the_time_spent_typing,
        cli::repl_stats_after_an_interrupt_leave_out_the_stopped_render,
        cli::closed_streams_and_byte_order_marks,
        cli::the_memory_budget_from_the_command_line,
        cli::endless_input_is_refused,
        cli::a_file_size_limit_is_a_write_error,
        cli::the_repl_survives_bytes_that_are_not_utf8,
        cli::output_files_keep_links_modes_and_long_names,
        cli::unwritable_output_names_are_usage_errors,
        cli::any_address_space_limit_runs_or_says_why,
        cli::errors_name_their_line_however_they_end,
        cli::shell_completions_know_every_option,
        farm::frames_are_selected_named_and_rendered_once,
        farm::shards_cover_every_frame_once_with_the_same_bytes,
        farm::skip_existing_leaves_finished_frames_alone,
        farm::exit_codes_tell_a_farm_what_to_retry,
        farm::crops_merge_into_the_full_picture,
        farm::progressive_and_thread_count_change_no_pixel,
        farm::movie_is_an_animated_png_of_the_frames,
        farm::gnu_parallel_shards_match_a_single_run,
        farm::a_self_rendering_script_is_not_traced_twice,
        interrupt::ctrl_c_in_a_batch_exits_130_and_leaves_no_file,
        interrupt::waits_for_input_give_way_to_ctrl_c,
        interrupt::every_interrupt_exits_130_flushed_and_clean,
        interrupt::ctrl_c_during_a_png_encode,
        interrupt::ctrl_c_in_the_repl_cancels_the_render_and_keeps_the_session,
        interrupt::kill_9_never_leaves_a_truncated_image,
        interrupt::one_ctrl_c_ends_every_wait_within_half_a_second,
        interrupt::a_time_limit_ends_the_run_with_124,
        lang::scripts_match_tclsh,
        lang::errors_name_file_and_line,
        lang::streaming_windows_are_invisible,
        lang::tcl_test_suite_agreement_holds,
        mesh::mesh_is_placed_and_lit,
        mesh::smooth_normals_are_computed_when_missing,
        mesh::bad_obj_files_are_located_errors,
        mesh::bundled_bunny_loads,
        mesh::obj_readers_agree_on_real_models,
        pov::refraction_matches_povray,
        pov::shapes_and_csg_match_povray,
        pov::image_mappings_match_povray,
        pov::spd_scenes_match_povray,
        pov::smooth_meshes_refract_the_same_whichever_way_they_are_wound,
        readme::the_opening_example_renders_the_picture_under_it,
        readme::first_scene_steps_render_their_pictures,
        readme::the_command_table_is_the_help_text,
        readme::every_link_resolves,
        readme::help_shows_a_whole_entry,
        render::lambert_pixel_under_parallel_light,
        render::point_light_falls_off_as_inverse_square,
        render::spot_light_falloff_matches_formula,
        render::shadows_are_black_or_tinted,
        render::mirror_shows_what_it_faces,
        render::same_picture_for_any_thread_count,
        render::sample_scenes_match_goldens,
        render::output_files_pass_netpbm,
        render::cli_renders_the_final_scene,
        render::no_light_warns,
        render::stats_and_heatmap,
        render::renders_reuse_the_tree_only_while_its_geometry_and_eye_stay,
        render::degenerate_triangles_are_skipped_with_one_warning,
        render::pictures_do_not_depend_on_where_the_scene_sits_or_its_scale,
        render::coplanar_triangles_show_the_one_added_first,
        render::coarse_smooth_meshes_have_no_shadow_terminator_notches,
        render::pngs_say_how_their_values_are_encoded,
        render::smooth_meshes_shade_the_same_whichever_way_they_are_wound,
        tidy::every_module_starts_with_a_doc_comment,
        tidy::layering_holds,
        tidy::every_test_is_registered,
    ];
    libtest_mimic::run(&args, trials).exit();
}
