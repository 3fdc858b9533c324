#pragma once

#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// camera: {driver: opencv, source: /dev/video0 | a video file | an image pattern | rtsp://...,
// rate_hz: 10, width: 0, height: 0 (0: the source's), jpeg_quality: 80}: JPEG frames through
// OpenCV's VideoCapture.
void make_opencv_camera(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
