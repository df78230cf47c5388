#version 310 es
#extension GL_EXT_clip_cull_distance : require
// Sensor maps of sensor-based lighting (render/gl_sensor.c): the scene's triangles into the
// hemicubes of many sensors at once. Instance i draws face i % 5 of sensor i / 5 into the
// sensor's tile of the atlas: the front face (looking along the normal) over the tile's lower
// part, then the half faces x = +1, x = -1, y = +1, y = -1 of the local frame (render/hemicube.h),
// each clipped to its own rectangle by four clip distances. Depth is reversed (EXT_clip_control,
// zero to one): z/w = near / distance, so float depth keeps its precision to any distance.
precision highp float;
precision highp int;

layout(location = 0) in vec3 a_pos; // m, vehicle frame
layout(location = 1) in vec3 a_nrm; // the visible side
layout(location = 2) in float a_albedo;
layout(location = 3) in vec4 a_sphere; // centre, signed radius; w = 0: flat

uniform highp sampler2D u_sensors; // row s: eye, t, b, n (texels 0..3, xyz)
uniform int u_tiles_x; // tiles per atlas row
uniform ivec2 u_tile; // tile size, texels: (face, 3 face), the front face then four halves
uniform int u_face; // front face texels across (size times supersampling)
uniform vec2 u_atlas; // atlas size, texels
uniform float u_near; // m

centroid out vec3 v_pos;
centroid out vec3 v_nrm;
flat out float v_albedo;
flat out vec4 v_sphere;

void main()
{
	int s = gl_InstanceID / 5, f = gl_InstanceID % 5;
	vec3 eye = texelFetch(u_sensors, ivec2(0, s), 0).xyz;
	vec3 t = texelFetch(u_sensors, ivec2(1, s), 0).xyz;
	vec3 b = texelFetch(u_sensors, ivec2(2, s), 0).xyz;
	vec3 n = texelFetch(u_sensors, ivec2(3, s), 0).xyz;
	vec3 w = a_pos - eye;
	vec3 q = vec3(dot(w, t), dot(w, b), dot(w, n));
	// Face coordinates: along the face (x), across it (y) and the distance in front of it.
	float d, x, y;
	if (f == 0) {
		d = q.z; x = q.x; y = q.y;
	} else if (f == 1) {
		d = q.x; x = q.y; y = 2.0 * q.z - d;
	} else if (f == 2) {
		d = -q.x; x = q.y; y = 2.0 * q.z - d;
	} else if (f == 3) {
		d = q.y; x = q.x; y = 2.0 * q.z - d;
	} else {
		d = -q.y; x = q.x; y = 2.0 * q.z - d;
	}
	gl_ClipDistance[0] = d + x;
	gl_ClipDistance[1] = d - x;
	gl_ClipDistance[2] = d + y;
	gl_ClipDistance[3] = d - y;
	// The face's rectangle in the atlas, texels.
	ivec2 tile = ivec2(s % u_tiles_x, s / u_tiles_x) * u_tile;
	vec2 org = vec2(tile), size = vec2(float(u_face));
	if (f > 0) {
		org.y += float(u_face + (f - 1) * (u_face / 2));
		size.y = float(u_face / 2);
	}
	// Face NDC [-1, 1] to atlas NDC, in clip space (times w = d).
	vec2 c = -1.0 + (2.0 * org + size) / u_atlas, k = size / u_atlas;
	gl_Position = vec4(c.x * d + k.x * x, c.y * d + k.y * y, u_near, d);
	// One-sided flat triangles seen from behind: every vertex fails the same plane.
	if (a_sphere.w == 0.0 && dot(a_nrm, eye - a_pos) <= 0.0)
		gl_Position = vec4(0.0, 0.0, 0.0, -1.0);
	v_pos = a_pos;
	v_nrm = a_nrm;
	v_albedo = a_albedo;
	v_sphere = a_sphere;
}
