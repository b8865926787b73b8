#pragma once
// The frame quantities computed from the state alone (FrameFill::of_state), when their block of
// frames is written: velocities, attitudes as quaternions, spins, and the binary's relative orbit,
// angles and libration (docs/equations.md §17). The frame schema's rows point at them.
#include "io/frame_schema.hpp"

namespace noether::io::of_state {

void velocity(const StateFrame& in, void* out);
void quaternion(const StateFrame& in, void* out);
void angular_velocity(const StateFrame& in, void* out);
void separation(const StateFrame& in, void* out);
void binary_position(const StateFrame& in, void* out);
void binary_velocity(const StateFrame& in, void* out);
void position_in_primary_frame(const StateFrame& in, void* out);
void velocity_in_primary_frame(const StateFrame& in, void* out);
void osculating_elements(const StateFrame& in, void* out);
void libration(const StateFrame& in, void* out);
void euler_angles(const StateFrame& in, void* out);
void secondary_euler_angles(const StateFrame& in, void* out);
void nutation_angles(const StateFrame& in, void* out);

}  // namespace noether::io::of_state
