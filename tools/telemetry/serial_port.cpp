#include "serial_port.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

namespace wmra {
namespace telemetry_cli {

int open_serial(const std::string& device) {
  const int fd = open(device.c_str(), O_RDWR | O_NOCTTY);
  if (fd < 0) throw IoError{device + ": " + std::strerror(errno)};
  termios t;
  if (tcgetattr(fd, &t) != 0) {
    const int error = errno;
    close(fd);
    throw IoError{device + ": not a serial port (" + std::strerror(error) + ")"};
  }
  cfmakeraw(&t);  // 8 data bits, no parity, no echo, no line editing
  t.c_cflag &= ~(tcflag_t)(CSTOPB | CRTSCTS);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, B115200) != 0 || cfsetospeed(&t, B115200) != 0 || tcsetattr(fd, TCSANOW, &t) != 0) {
    const int error = errno;
    close(fd);
    throw IoError{device + ": cannot set 115200 8N1 (" + std::strerror(error) + ")"};
  }
  tcflush(fd, TCIOFLUSH);
  return fd;
}

}  // namespace telemetry_cli
}  // namespace wmra
