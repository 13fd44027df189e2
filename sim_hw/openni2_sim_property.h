#pragma once
// Answers an OpenNI2 getProperty call with one fixed-size value: the caller's buffer must be
// exactly the value's size, as OpenNI2's own drivers require.
#include <cstring>

#include <OniCTypes.h>

namespace sim_hw {

template <typename T>
OniStatus put_property(void* data, int* size, const T& value) {
  if (*size != static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
  std::memcpy(data, &value, sizeof(T));
  return ONI_STATUS_OK;
}

}  // namespace sim_hw
