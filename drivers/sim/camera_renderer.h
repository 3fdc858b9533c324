#pragma once

#include <opencv2/core.hpp>
#include <random>

#include "core/geometry/pose2d.h"
#include "core/vision/camera_pose.h"
#include "core/vision/omni_camera_model.h"
#include "drivers/sim/camera_noise.h"
#include "drivers/sim/camera_scene.h"

namespace mobot::sim {

// Camera frames rendered from the 3D world so that vision code runs on real pixels: floor tiles,
// textured walls, ceiling, boxes, landmarks, obstacles and moving targets, with a depth test so a
// target behind a pillar or a wall is hidden, then the camera's noise. Images are BGR CV_8UC3.
// Deterministic: the same scene, pose, noise state and rng state give the same image.
//
// Every pixel has its exact ray (a tilted camera's columns are not constant azimuths). Objects are
// intersected exactly per pixel. Walls are not: one horizontal ray cast on the floor grid per
// azimuth bin, reused by all pixels in the bin, with bins a quarter of a column wide (pinhole) or
// half a pixel at the rim (omni), so a wall edge may sit up to that far from its exact place.
//
// Pixel (u, v) has its centre at integer coordinates, u to the right and v down, as
// OmniCameraModel::direction and PinholeCamera's principal point (width/2, height/2) read them.

// The pinhole camera at `pose`: the ray through pixel (u, v) is
//   focal_px * forward + (width/2 - u) * left + (height/2 - v) * up
// in the map frame, forward = (cos p cos y, cos p sin y, sin p), left = (-sin y, cos y, 0).
// Throws std::invalid_argument for a non-finite pose, a non-positive size, a field of view
// outside (0, pi) or bad scene options.
cv::Mat render_perspective(const CameraScene& scene, const vision::CameraPose& pose,
                           const vision::PinholeCamera& camera, const CameraNoise& noise,
                           std::mt19937_64& rng);

// The omnidirectional camera on the robot at `base_pose` (map frame), its single viewpoint
// camera_height_m above the floor on the base's vertical axis: pixel p inside the mirror's ring
// shows what lies along model.direction(p) (azimuth from the heading); the centre disc and the
// corners outside the ring are dark grey. Throws std::invalid_argument for a non-finite pose or
// height, a model whose ring is empty or not finite (xi must exceed sin(max_elevation_rad)), or
// bad scene options.
cv::Mat render_omni(const CameraScene& scene, const geometry::Pose2D& base_pose,
                    double camera_height_m, const vision::OmniCameraModel& model,
                    const CameraNoise& noise, std::mt19937_64& rng);

}  // namespace mobot::sim
