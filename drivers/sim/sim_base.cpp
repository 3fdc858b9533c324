#include "drivers/sim/sim_base.h"

#include "core/kinematics/diff_drive.h"
#include "drivers/sim/sim_backend.h"

namespace mobot::sim {

void SimBase::set_wheel_command(const msgs::WheelCommand& command) {
  // The motor controllers are given the nominal geometry's wheel speeds; how far the true wheels
  // differ from it is the Simulator's systematic error, as on the real base.
  const RobotProfile& profile = backend_.profile();
  if (profile.steering) {
    backend_.simulator().set_steered_command({command.drive_mps, command.steering_rad});
    return;
  }
  backend_.simulator().set_command(kinematics::twist_from_wheels(
      {command.left_radps * profile.wheel_radius_m, command.right_radps * profile.wheel_radius_m},
      profile.track_m));
}

std::optional<msgs::WheelEncoders> SimBase::read_encoders(double now_s) {
  msgs::WheelEncoders encoders = backend_.simulator().read_encoders();
  encoders.stamp_s = now_s;
  return encoders;
}

std::vector<msgs::Contact> SimBase::take_contacts() {
  std::vector<msgs::Contact> contacts;
  for (auto& collision : backend_.simulator().take_collisions()) {
    contacts.push_back({backend_.simulator().time_s(), std::move(collision.with), collision.pose});
  }
  return contacts;
}

}  // namespace mobot::sim
