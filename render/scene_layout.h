/* SPDX-License-Identifier: MIT */
/*
 * Where the built-in scenes' geometry and paint lie (private to render/): the analytic scenes
 * of render/scene.c and their triangle meshes in render/scene_mesh.c use these same numbers.
 * Metres in the vehicle frame (x forward, y left, z up) unless the name says otherwise.
 */
#ifndef HL_RENDER_SCENE_LAYOUT_H
#define HL_RENDER_SCENE_LAYOUT_H

#define ROAD_START_M (-10.0) /* the road runs on under and behind the vehicle */
#define MARK_EDGE_Y_M 3.35 /* centre of the solid edge lines */
#define MARK_EDGE_W_M 0.15
#define MARK_CENTRE_W_M 0.12
#define DASH_M 3.0 /* centre line: 3 m dash, 6 m gap */
#define DASH_PERIOD_M 9.0
#define POST_Y_M 4.25 /* posts half a metre beyond the shoulder line */
#define POST_SIDE_M 0.12
#define POST_HEIGHT_M 1.0
#define POST_STEP_M 10.0
#define GRASS_HALF_WIDTH_M 40.0
#define GRID_STEP_M 10.0
#define GRID_LINE_M 0.25
#define WALL_HALF_WIDTH_M 20.0
#define WALL_HEIGHT_M 10.0
#define WALL_LINE_DEG 0.25 /* lines 0.25° wide, as seen from the lamps */
#define WALL_STEP_DEG 5.0

/* Reflectances (albedo) of the road scene's surfaces, shared with the moving scene. */
#define HL_ALBEDO_ROAD 0.12
#define HL_ALBEDO_MARKING 0.6
#define HL_ALBEDO_SHOULDER 0.07
#define HL_ALBEDO_POST 0.8

#endif
