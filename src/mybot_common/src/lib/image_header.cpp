#include "mybot_common/image_header.h"

#include <algorithm>
#include <cctype>
#include <fstream>

namespace mybot_common
{

namespace
{
// PNM: "P5", then width, height (and maxval) as decimal text, separated by whitespace and
// comments from '#' to the end of the line.
bool readPnmNumber(std::istream& in, long& out)
{
  int c = in.get();
  while (in && (std::isspace(c) || c == '#'))
  {
    if (c == '#')
      while (in && c != '\n')
        c = in.get();
    c = in.get();
  }
  if (!in || !std::isdigit(c))
    return false;
  out = 0;
  while (in && std::isdigit(c))
  {
    if (out > 1000000000L)
      return false;
    out = out * 10 + (c - '0');
    c = in.get();
  }
  return true;
}

long bigEndian32(const unsigned char* p)
{
  return (static_cast<long>(p[0]) << 24) | (static_cast<long>(p[1]) << 16) | (static_cast<long>(p[2]) << 8) | p[3];
}
}  // namespace

bool peekImageSize(const std::string& path, long& width, long& height)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return false;
  unsigned char head[24] = {};
  in.read(reinterpret_cast<char*>(head), 2);
  if (in.gcount() == 2 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6')
    return readPnmNumber(in, width) && readPnmNumber(in, height);
  // PNG: 8-byte signature, then the IHDR chunk: length, "IHDR", width, height (big-endian).
  in.read(reinterpret_cast<char*>(head) + 2, 22);
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() == 22 && std::equal(kPng, kPng + 8, head) && std::string(head + 12, head + 16) == "IHDR")
  {
    width = bigEndian32(head + 16);
    height = bigEndian32(head + 20);
    return true;
  }
  return false;
}

std::string imageSizeError(const std::string& path, long width, long height, long max_side,
                           const std::string& parameter)
{
  if (width <= max_side && height <= max_side)
    return "";
  return "image " + path + " declares " + std::to_string(width) + " x " + std::to_string(height) +
         " pixels, more than " + std::to_string(max_side) + " on a side (parameter " + parameter + ")";
}

std::string declaredImageSizeError(const std::string& path, long max_side, const std::string& parameter)
{
  long w = 0, h = 0;
  if (!peekImageSize(path, w, h))
    return "";
  return imageSizeError(path, w, h, max_side, parameter);
}

}  // namespace mybot_common
