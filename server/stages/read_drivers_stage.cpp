#include "server/stages/read_drivers_stage.h"

namespace mobot::server {
namespace {

template <class Msg>
void poll(drivers::SensorDriver<Msg>* driver, TickContext& context, std::optional<Msg>& out) {
  if (!driver) return;
  out = driver->poll(context.now_s);
  if (const auto status = driver->status(); !status.ok) {
    context.device_faults.emplace_back(std::string(driver->name()), status.reason);
  }
}

}  // namespace

void ReadDriversStage::step(TickContext& context) {
  drivers::BaseDriver& base = *drivers_.base;
  context.encoders = base.read_encoders(context.now_s);
  context.contacts = base.take_contacts();
  context.estop_button = base.estop_button_pressed();
  if (const auto status = base.status(); !status.ok) {
    context.device_faults.emplace_back("encoders", status.reason);
  }
  poll(drivers_.laser.get(), context, context.scan);
  poll(drivers_.sonar.get(), context, context.sonar);
  poll(drivers_.ir.get(), context, context.ir);
  poll(drivers_.compass.get(), context, context.compass);
  poll(drivers_.bearings.get(), context, context.bearings);
  poll(drivers_.camera.get(), context, context.image);
  poll(drivers_.head_range.get(), context, context.head_range);
  if (drivers_.pan_tilt) context.head = drivers_.pan_tilt->current();
}

}  // namespace mobot::server
