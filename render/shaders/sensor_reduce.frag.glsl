#version 310 es
// Second half of the reduction (render/gl_sensor.c): the irradiance of each sensor,
// E = sum F_ij L_ij, as the sum of its tile's row sums (sensor_rows.frag.glsl). Fragment
// (tx, ty) is the sensor of tile (tx, ty), i.e. sensor ty * tiles_x + tx.
precision highp float;
precision highp int;

uniform highp sampler2D u_rows; // row sums, one column per tile column
uniform int u_tile_h; // tile height, texels

out vec4 o_out;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	float e = 0.0;
	for (int y = 0; y < u_tile_h; y++)
		e += texelFetch(u_rows, ivec2(px.x, px.y * u_tile_h + y), 0).r;
	o_out = vec4(e, 0.0, 0.0, 0.0);
}
