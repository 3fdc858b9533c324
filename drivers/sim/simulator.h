#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/compass_reading.h"
#include "core/msgs/landmark_bearing.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/head_range.h"
#include "core/msgs/sonar_ring.h"
#include "core/msgs/tilt_scan.h"
#include "core/msgs/twist.h"
#include "core/msgs/wheel_encoders.h"
#include "drivers/sim/body_collider.h"
#include "drivers/sim/camera_scene.h"
#include "drivers/sim/moving_target.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/robot_profile.h"
#include "drivers/sim/sharp_ir_adc.h"
#include "drivers/sim/wheel_slip.h"
#include "drivers/sim/world.h"

namespace mobot::sim {

struct Collision {
  std::string with;       // "wall", a box name, or "obstacle <id>"
  geometry::Pose2D pose;  // where the robot stopped
};

// A cylinder standing on the floor, dropped into the world at run time.
struct Obstacle {
  int id = 0;
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.0;
  double height_m = 0.0;
};

// The simulated robot in its world: true pose, drive with systematic and random wheel errors and
// slip on the floor, and the sensors of the profile, each seeing the world at its own height.
// Deterministic for a given seed and call sequence: no wall clock, no threads. Each noise source
// draws from its own random stream, so reading a sensor more or less often does not change how
// the robot drives.
class Simulator {
 public:
  // The robot starts at world.start.
  Simulator(World world, RobotProfile profile, std::uint64_t seed);

  // Advances time by dt_s (>= 0, else std::invalid_argument) and drives the robot with the
  // commanded body velocity, clamped to the profile limits. The body never enters an obstacle: on
  // contact it stops where it touches, the command drops to zero until the next set_command, and a
  // Collision is queued. Pushing on against an obstacle without having moved freely since the last
  // collision is blocked but not counted again.
  void step(double dt_s);
  double time_s() const { return time_s_; }

  // A differential base: the body velocity its wheel controllers are asked for. A steered base
  // takes it as the tricycle input that asks for it (TricycleModel's inverse kinematics).
  void set_command(const msgs::Twist& command);
  // A steered base's own command: the driven wheel's speed and the steering angle, clamped to
  // the profile's limits (std::logic_error on a differential base).
  void set_steered_command(const kinematics::TricycleInput& input);
  // The body velocity commanded, as the current steering angle makes it; zero after a collision.
  msgs::Twist command() const;
  // The steering wheel's true angle (0 on a differential base): it slews toward the command.
  double steering_rad() const { return steering_rad_; }

  geometry::Pose2D true_pose() const { return pose_; }
  int collision_count() const { return collision_count_; }
  // The queued collisions, oldest first; the queue is left empty.
  std::vector<Collision> take_collisions();

  // Cumulative ticks of the true wheel rotations, stamped time_s.
  msgs::WheelEncoders read_encoders();
  // Ray cast in the laser plane against walls, boxes whose z range contains the laser height and
  // obstacles at least that tall; gaussian range noise. No return reads range_max_m + 1. A full
  // circle has no beam twice: 360 deg at 0.5 deg is 720 beams.
  msgs::LaserScan read_laser();
  // The nodding laser at its true pitch (the caller assigns the pitch the scan reports): a 180 deg
  // fan at step_rad in the tilted plane, cast in 3D against the floor, the full-height walls, the
  // boxes and the obstacles, with the 2D laser's range noise and a reflectance per surface.
  msgs::TiltScan read_tilt_laser(double true_pitch_rad, double step_rad);
  // Per sonar the nearest echo across its cone (several rays) at the sonar height; range_max_m
  // when nothing echoes.
  msgs::SonarRing read_sonar();
  // Per IR sensor of the profile, what its microcontroller reports: the ADC count for the nearest
  // object across the beam at the IR height (walls, boxes whose z range contains it, obstacles at
  // least that tall), through the sensor model of profile().ir_adc (SharpIrAdc).
  std::vector<int> read_ir_adc();
  // True heading plus gaussian noise, wrapped.
  msgs::CompassReading read_compass();
  // The omnidirectional camera at the base centre: every world landmark no further than
  // profile().camera_range_m whose line of sight in the laser plane (walls, boxes and obstacles
  // at least that tall) is clear up to the landmark's surface gives its bearing from the heading
  // plus gaussian noise (profile().bearing_sigma_rad), wrapped; in the world's landmark order.
  msgs::LandmarkBearings read_landmark_bearings();

  // Whether the body at `pose` would touch a wall, a box or an obstacle (or leave the floor plan).
  bool pose_collides(const geometry::Pose2D& pose) const;

  // Adds a cylinder (radius and height > 0 and finite, else std::invalid_argument); ids count
  // from 1 after construction or reset. Returns the id.
  int add_obstacle(double x_m, double y_m, double radius_m, double height_m);
  bool remove_obstacle(int id);
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }
  // Adds a coloured ball moving along its path from now on (MovingTarget's checks: throws
  // std::invalid_argument naming the field); ids count from 1 after construction or reset.
  int add_target(const MovingTargetSpec& spec);
  bool remove_target(int id);
  std::size_t target_count() const { return targets_.size(); }
  // What the cameras see of the dynamic world now.
  std::vector<SceneSphere> target_spheres() const;
  std::vector<SceneCylinder> obstacle_cylinders() const;
  // The ultrasonic ranger on the pan/tilt head (profile().pan_tilt_camera) with the head at
  // `joints`: the nearest echo across its cone, in the horizontal plane at the lens's height
  // (walls, boxes and obstacles that tall, and the moving targets' spheres where that plane cuts
  // them), with gaussian noise of range_noise_fraction. Nothing without a head.
  msgs::HeadRange read_head_range(const vision::PanTilt& joints);
  // Lifts the robot and sets it down at `pose` (a kidnap): the wheels do not turn, so the
  // encoders do not see it; everything else goes on.
  void teleport(const geometry::Pose2D& pose) { pose_ = pose; }
  // Puts the robot at `pose` at time 0 with encoders, collisions and obstacles cleared, the
  // command zero and the random streams reseeded.
  void reset(const geometry::Pose2D& pose, std::uint64_t seed);

  const World& world() const { return world_; }
  const RobotProfile& profile() const { return profile_; }

 private:
  struct WheelAngles {
    double left_rad = 0.0;
    double right_rad = 0.0;
  };

  void update_wheel_noise(double dt_s);
  // The body velocity the drive gives over the next dt_s: the command on a differential base;
  // a steered base first slews its steering toward the command (with its bias).
  msgs::Twist drive_twist(double dt_s);
  // Moves through one slice of the step: the wheels turn by `rotation` (what the encoders count)
  // and roll `ground` over the floor (the same without slip); false when it ended in a collision.
  bool drive_substep(const WheelAngles& rotation, const WheelAngles& ground);
  // Where rolling `fraction` of `ground` (wheel angles over the floor) takes the true base.
  geometry::Pose2D pose_after(const geometry::Pose2D& start, const WheelAngles& ground,
                              double fraction) const;
  std::optional<std::string> contact(const geometry::Pose2D& pose) const;
  void record_collision(const std::string& with);
  // Lowers the fan's ranges where a beam meets an obstacle at least as tall as the laser plane.
  void add_obstacles_to_fan(geometry::Point2D from, double first_angle_rad, double increment_rad,
                            std::span<double> ranges_m) const;
  // Nearest hit in the laser plane: static world and obstacles at least as tall as the plane.
  std::optional<double> nearest_in_plane(geometry::Point2D from, double angle_rad,
                                         double max_range_m) const;
  // Nearest hit in the slice `plane` of the world at `height_m`, and obstacles that tall.
  std::optional<double> nearest_at(const RayCaster& plane, double height_m, geometry::Point2D from,
                                   double angle_rad, double max_range_m) const;

  World world_;
  RobotProfile profile_;
  // The world as each sensor sees it; sensors at one height share a slice.
  std::shared_ptr<const RayCaster> laser_plane_;
  std::shared_ptr<const RayCaster> sonar_plane_;
  std::shared_ptr<const RayCaster> ir_plane_;  // null without an IR ring
  RayCaster walls_;  // the floor plan alone: walls are full height for the nodding laser
  std::shared_ptr<const RayCaster> head_plane_;  // null without a pan/tilt head
  BodyCollider body_;
  WheelSlip slip_;
  SharpIrAdc ir_adc_;

  geometry::Pose2D pose_;
  double time_s_ = 0.0;
  msgs::Twist command_;
  kinematics::TricycleInput steered_command_;
  double steering_rad_ = 0.0;
  WheelAngles wheel_angles_;
  double left_speed_error_ = 0.0;  // fraction of the commanded wheel speed
  double right_speed_error_ = 0.0;
  std::vector<Collision> collisions_;
  int collision_count_ = 0;
  bool in_contact_ = false;  // collided and has not moved freely since
  std::vector<Obstacle> obstacles_;
  int next_obstacle_id_ = 1;
  struct Target {
    int id = 0;
    MovingTarget target;
    double added_at_s = 0.0;
  };
  std::vector<Target> targets_;
  int next_target_id_ = 1;

  std::mt19937_64 drive_rng_;
  std::mt19937_64 laser_rng_;
  std::mt19937_64 sonar_rng_;
  std::mt19937_64 compass_rng_;
  std::mt19937_64 camera_rng_;
  std::mt19937_64 tilt_rng_;
  std::mt19937_64 slip_rng_;
  std::mt19937_64 ir_rng_;
  std::mt19937_64 head_range_rng_;
};

}  // namespace mobot::sim
