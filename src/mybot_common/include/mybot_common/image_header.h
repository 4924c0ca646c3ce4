// The size an image file declares, read from its header without decoding it: a map whose header
// claims 200000 x 200000 pixels is refused before 40 GB are allocated (OpenCV's imread would throw
// or try). No ROS, no OpenCV.
#pragma once

#include <string>

namespace mybot_common
{

// The default of the ~max_image_side parameters (map_server, gazebo_lite's image worlds):
// 20000 x 20000 cells is a 1 km square at 5 cm, 400 MB decoded.
constexpr long kDefaultMaxImageSide = 20000;

// PNM (P1-P6) and PNG headers. False if the file cannot be read or is in another format (then
// decode it and check the decoded size).
bool peekImageSize(const std::string& path, long& width, long& height);

// An error message if the image declares more than max_side pixels on a side ("image
// /m/big.pgm declares 200000 x 200000 pixels, more than 20000 on a side (parameter
// ~max_image_side)"), else "". `parameter` names the limit's parameter for the message.
std::string imageSizeError(const std::string& path, long width, long height, long max_side,
                           const std::string& parameter);
std::string declaredImageSizeError(const std::string& path, long max_side, const std::string& parameter);

}  // namespace mybot_common
