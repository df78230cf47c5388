/* SPDX-License-Identifier: MIT */
#include "world/camera.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#include "lamp/angles.h"

#define DEG (M_PI / 180.0)

static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double r[3])
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalise(double v[3])
{
	const double n = sqrt(dot(v, v));

	v[0] /= n;
	v[1] /= n;
	v[2] /= n;
}

void hl_camera_basis(const struct hl_camera *cam, double r[3], double u[3], double f[3])
{
	memcpy(f, cam->dir, sizeof(double) * 3);
	normalise(f);
	cross(f, cam->up, r);
	normalise(r);
	cross(r, f, u);
}

static double tan_half(const struct hl_camera *cam)
{
	return tan(cam->fov_y_deg * DEG / 2);
}

void hl_camera_ray(const struct hl_camera *cam, double x, double y, double d[3])
{
	const double t = tan_half(cam), aspect = (double)cam->width / cam->height;
	const double sx = (2.0 * x / cam->width - 1.0) * t * aspect;
	const double sy = (1.0 - 2.0 * y / cam->height) * t;
	double r[3], u[3], f[3];

	hl_camera_basis(cam, r, u, f);
	for (int i = 0; i < 3; i++)
		d[i] = f[i] + sx * r[i] + sy * u[i];
}

int hl_camera_project(const struct hl_camera *cam, const double p[3], double *ret_x, double *ret_y)
{
	const double t = tan_half(cam), aspect = (double)cam->width / cam->height;
	double r[3], u[3], f[3], d[3], z;

	hl_camera_basis(cam, r, u, f);
	for (int i = 0; i < 3; i++)
		d[i] = p[i] - cam->pos_m[i];
	z = dot(d, f);
	if (!(z > 0.0))
		return -EDOM;
	*ret_x = (dot(d, r) / z / (t * aspect) + 1.0) * cam->width / 2;
	*ret_y = (1.0 - dot(d, u) / z / t) * cam->height / 2;
	return 0;
}

void hl_camera_world_to_camera(const struct hl_camera *cam, float m[16])
{
	double r[3], u[3], f[3];

	hl_camera_basis(cam, r, u, f);
	/* Row-vector convention: column j of the 3x3 part is camera axis j. */
	for (int i = 0; i < 3; i++) {
		m[i * 4 + 0] = (float)r[i];
		m[i * 4 + 1] = (float)u[i];
		m[i * 4 + 2] = (float)f[i];
		m[i * 4 + 3] = 0.0f;
	}
	m[12] = (float)-dot(cam->pos_m, r);
	m[13] = (float)-dot(cam->pos_m, u);
	m[14] = (float)-dot(cam->pos_m, f);
	m[15] = 1.0f;
}

void hl_camera_world_to_ndc(const struct hl_camera *cam, float m[16])
{
	const double t = tan_half(cam), aspect = (double)cam->width / cam->height;
	float c[16];
	/*
	 * Camera (x, y, z, 1) to homogeneous NDC: x_ndc = (x / (z t aspect) + 1) / 2,
	 * y_ndc = (1 - y / (z t)) / 2, w = z. As a row-vector matrix P, column j gives coordinate j.
	 */
	const double p[4][4] = {
		{ 0.5 / (t * aspect), 0.0, 0.0, 0.0 },
		{ 0.0, -0.5 / t, 0.0, 0.0 },
		{ 0.5, 0.5, 1.0, 1.0 },
		{ 0.0, 0.0, 0.0, 0.0 },
	};

	hl_camera_world_to_camera(cam, c);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double s = 0.0;

			for (int k = 0; k < 4; k++)
				s += c[i * 4 + k] * p[k][j];
			m[i * 4 + j] = (float)s;
		}
}

void hl_lamp_pose_default(int side, struct hl_lamp_pose *ret)
{
	*ret = (struct hl_lamp_pose){
		.pos_m = { 0.0, side == 0 ? HL_LAMP_Y_M : -HL_LAMP_Y_M, HL_LAMP_Z_M },
		.yaw_deg = 0.0,
		.pitch_deg = -atan(0.01) / DEG,
	};
}

void hl_lamp_basis(const struct hl_lamp_pose *pose, double x[3], double y[3], double z[3])
{
	hl_mount_basis(pose->yaw_deg, pose->pitch_deg, x, y, z);
}

void hl_lamp_to_lamp_space(const struct hl_lamp_pose *pose, const double p[3], double ret[3])
{
	hl_mount_to_local(pose->pos_m, pose->yaw_deg, pose->pitch_deg, p, ret);
}
