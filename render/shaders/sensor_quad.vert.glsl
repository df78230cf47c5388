#version 310 es
// A quad over the whole viewport, no vertex buffer (GLSL ES 3.10, for the sensor passes).
void main()
{
	vec2 c = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
	gl_Position = vec4(2.0 * c - 1.0, 0.0, 1.0);
}
