//! The topics a flight log holds: PX4's uORB names and field names (a subset of each message's
//! fields, in PX4's units and frames) so PX4's tools read them, and this project's own topics.
//! Each topic's message id is its position in [`Topic::ALL`]. Pure.
//!
//! Own topics:
//! - `external_wrench_estimate`: f̂_e world NED `force[3]` [N], τ̂_e body FRD `torque[3]` [N·m],
//!   `mass` m_e + f̂_ez / g [kg];
//! - `external_wrench_truth`: the plant's true external `force[3]` (world NED) [N]: the scripted
//!   force plus the aerodynamic drag, wind included; `torque[3]` (body FRD) [N·m], the true
//!   `mass` [kg], `mass_mismatch_force`, the (m_r − m_e) g [N] (down) the estimator adds to
//!   `force[2]`, the air's `wind_velocity[3]` [m/s] and the drag `wind_force[3]` [N] (world NED,
//!   docs/model.md §5.1, eq. (5.2));
//! - `vehicle_*_groundtruth`: PX4 SITL's topics of the plant's true state, beside the estimate
//!   the controllers fly on;
//! - `controller_errors`: e_p, e_v (world NED) [m, m/s], e_R, e_ω of the geometric law (or e_η,
//!   ė_η of the RPY laws) [rad, rad/s];
//! - `allocation_status`: the applied collective thrust [N] and body torque FRD [N·m] (G_q ω² of
//!   the commanded speeds) and whether the allocation saturated.

/// One logged topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Topic {
    /// Attitude quaternion (w, x, y, z), body FRD → world NED.
    VehicleAttitude,
    /// Body rates, FRD [rad/s].
    VehicleAngularVelocity,
    /// Position [m], velocity [m/s], acceleration [m/s²] (world NED) and heading [rad].
    VehicleLocalPosition,
    /// Latitude, longitude [deg] and altitude AMSL [m].
    VehicleGlobalPosition,
    /// Desired attitude quaternion and normalised thrust vector, body FRD.
    VehicleAttitudeSetpoint,
    /// Position, velocity and acceleration setpoints (world NED; NaN where not set) and yaw.
    VehicleLocalPositionSetpoint,
    /// Arming state, navigation state, vehicle type, failsafe.
    VehicleStatus,
    /// Landed, maybe landed, ground contact, free fall.
    VehicleLandDetected,
    /// Commanded rotor speed over the maximum, per rotor [-] (NaN past the rotor count).
    ActuatorMotors,
    /// Collective thrust over the maximum, body FRD (z negative up) [-].
    VehicleThrustSetpoint,
    /// Body torque over each axis' authority, FRD [-].
    VehicleTorqueSetpoint,
    /// Battery voltage, current, charge drawn, remaining fraction.
    BatteryStatus,
    /// Gyroscope [rad/s] and accelerometer [m/s²], body FRD.
    SensorCombined,
    /// The wrench estimator's output.
    ExternalWrenchEstimate,
    /// The plant's true external wrench and mass.
    ExternalWrenchTruth,
    /// The controller's tracking errors.
    ControllerErrors,
    /// The applied wrench and the allocation's saturation.
    AllocationStatus,
    /// The plant's true attitude (fields of [`Topic::VehicleAttitude`]).
    VehicleAttitudeGroundtruth,
    /// The plant's true body rates (fields of [`Topic::VehicleAngularVelocity`]).
    VehicleAngularVelocityGroundtruth,
    /// The plant's true position, velocity and acceleration (fields of
    /// [`Topic::VehicleLocalPosition`]).
    VehicleLocalPositionGroundtruth,
}

/// Width of `actuator_motors.control` (PX4's).
pub const ACTUATOR_MOTORS: usize = 12;

impl Topic {
    /// Every topic, in message-id order.
    pub const ALL: [Topic; 20] = [
        Self::VehicleAttitude,
        Self::VehicleAngularVelocity,
        Self::VehicleLocalPosition,
        Self::VehicleGlobalPosition,
        Self::VehicleAttitudeSetpoint,
        Self::VehicleLocalPositionSetpoint,
        Self::VehicleStatus,
        Self::VehicleLandDetected,
        Self::ActuatorMotors,
        Self::VehicleThrustSetpoint,
        Self::VehicleTorqueSetpoint,
        Self::BatteryStatus,
        Self::SensorCombined,
        Self::ExternalWrenchEstimate,
        Self::ExternalWrenchTruth,
        Self::ControllerErrors,
        Self::AllocationStatus,
        Self::VehicleAttitudeGroundtruth,
        Self::VehicleAngularVelocityGroundtruth,
        Self::VehicleLocalPositionGroundtruth,
    ];

    /// The message id of its data.
    pub fn msg_id(self) -> u16 {
        self as u16
    }

    /// The uORB topic name.
    pub fn name(self) -> &'static str {
        match self {
            Self::VehicleAttitude => "vehicle_attitude",
            Self::VehicleAngularVelocity => "vehicle_angular_velocity",
            Self::VehicleLocalPosition => "vehicle_local_position",
            Self::VehicleGlobalPosition => "vehicle_global_position",
            Self::VehicleAttitudeSetpoint => "vehicle_attitude_setpoint",
            Self::VehicleLocalPositionSetpoint => "vehicle_local_position_setpoint",
            Self::VehicleStatus => "vehicle_status",
            Self::VehicleLandDetected => "vehicle_land_detected",
            Self::ActuatorMotors => "actuator_motors",
            Self::VehicleThrustSetpoint => "vehicle_thrust_setpoint",
            Self::VehicleTorqueSetpoint => "vehicle_torque_setpoint",
            Self::BatteryStatus => "battery_status",
            Self::SensorCombined => "sensor_combined",
            Self::ExternalWrenchEstimate => "external_wrench_estimate",
            Self::ExternalWrenchTruth => "external_wrench_truth",
            Self::ControllerErrors => "controller_errors",
            Self::AllocationStatus => "allocation_status",
            Self::VehicleAttitudeGroundtruth => "vehicle_attitude_groundtruth",
            Self::VehicleAngularVelocityGroundtruth => "vehicle_angular_velocity_groundtruth",
            Self::VehicleLocalPositionGroundtruth => "vehicle_local_position_groundtruth",
        }
    }

    /// The fields, as the format message declares them (`type name;` each, timestamp first).
    pub fn fields(self) -> &'static str {
        match self {
            Self::VehicleAttitude | Self::VehicleAttitudeGroundtruth => "uint64_t timestamp;float[4] q;",
            Self::VehicleAngularVelocity | Self::VehicleAngularVelocityGroundtruth => {
                "uint64_t timestamp;float[3] xyz;"
            }
            Self::VehicleLocalPosition | Self::VehicleLocalPositionGroundtruth => {
                "uint64_t timestamp;float x;float y;float z;float vx;float vy;float vz;float ax;float ay;\
                 float az;float heading;bool xy_valid;bool z_valid;bool v_xy_valid;bool v_z_valid;"
            }
            Self::VehicleGlobalPosition => "uint64_t timestamp;double lat;double lon;float alt;",
            Self::VehicleAttitudeSetpoint => "uint64_t timestamp;float[4] q_d;float[3] thrust_body;",
            Self::VehicleLocalPositionSetpoint => {
                "uint64_t timestamp;float x;float y;float z;float vx;float vy;float vz;float[3] acceleration;\
                 float yaw;"
            }
            Self::VehicleStatus => {
                "uint64_t timestamp;uint8_t arming_state;uint8_t nav_state;uint8_t vehicle_type;bool failsafe;"
            }
            Self::VehicleLandDetected => {
                "uint64_t timestamp;bool freefall;bool ground_contact;bool maybe_landed;bool landed;"
            }
            Self::ActuatorMotors => "uint64_t timestamp;float[12] control;",
            Self::VehicleThrustSetpoint | Self::VehicleTorqueSetpoint => "uint64_t timestamp;float[3] xyz;",
            Self::BatteryStatus => {
                "uint64_t timestamp;float voltage_v;float current_a;float discharged_mah;float remaining;\
                 uint8_t cell_count;bool connected;"
            }
            Self::SensorCombined => {
                "uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;\
                 int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;\
                 uint32_t accelerometer_integral_dt;"
            }
            Self::ExternalWrenchEstimate => "uint64_t timestamp;float[3] force;float[3] torque;float mass;",
            Self::ExternalWrenchTruth => {
                "uint64_t timestamp;float[3] force;float[3] torque;float mass;float mass_mismatch_force;\
                 float[3] wind_velocity;float[3] wind_force;"
            }
            Self::ControllerErrors => "uint64_t timestamp;float[3] e_p;float[3] e_v;float[3] e_r;float[3] e_omega;",
            Self::AllocationStatus => "uint64_t timestamp;float thrust;float[3] torque;bool saturated;",
        }
    }

    /// Payload bytes of one record (after the message id): what [`Self::fields`] declares
    /// (checked by a test against [`Self::declared_size`]).
    pub fn size(self) -> usize {
        match self {
            Self::VehicleAttitude | Self::VehicleAttitudeGroundtruth => 24,
            Self::VehicleAngularVelocity
            | Self::VehicleAngularVelocityGroundtruth
            | Self::VehicleThrustSetpoint
            | Self::VehicleTorqueSetpoint => 20,
            Self::VehicleLocalPosition | Self::VehicleLocalPositionGroundtruth => 52,
            Self::VehicleGlobalPosition => 28,
            Self::VehicleAttitudeSetpoint => 36,
            Self::VehicleLocalPositionSetpoint => 48,
            Self::VehicleStatus | Self::VehicleLandDetected => 12,
            Self::ActuatorMotors => 8 + 4 * ACTUATOR_MOTORS,
            Self::BatteryStatus => 26,
            Self::SensorCombined => 44,
            Self::ExternalWrenchEstimate => 36,
            Self::ExternalWrenchTruth => 64,
            Self::ControllerErrors => 56,
            Self::AllocationStatus => 25,
        }
    }

    /// Payload bytes of one record as [`Self::fields`] declares them.
    pub fn declared_size(self) -> usize {
        self.fields()
            .split(';')
            .filter(|f| !f.is_empty())
            .map(|f| {
                let ty = f.split_whitespace().next().unwrap_or("");
                let (base, count) = match ty.split_once('[') {
                    Some((base, n)) => (base, n.trim_end_matches(']').parse::<usize>().unwrap_or(0)),
                    None => (ty, 1),
                };
                let width = match base {
                    "uint64_t" | "int64_t" | "double" => 8,
                    "float" | "uint32_t" | "int32_t" => 4,
                    "uint16_t" | "int16_t" => 2,
                    _ => 1,
                };
                width * count
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_follow_the_table() {
        for (i, t) in Topic::ALL.iter().enumerate() {
            assert_eq!(usize::from(t.msg_id()), i, "{}", t.name());
        }
    }

    #[test]
    fn every_topic_starts_with_its_timestamp() {
        for t in Topic::ALL {
            assert!(t.fields().starts_with("uint64_t timestamp;"), "{}", t.name());
            assert!(!t.fields().contains(' ') || t.fields().split(';').all(|f| f.matches(' ').count() <= 1));
        }
    }

    #[test]
    fn sizes_are_what_the_formats_declare() {
        for t in Topic::ALL {
            assert_eq!(t.size(), t.declared_size(), "{}", t.name());
        }
    }

    #[test]
    fn sizes_count_arrays_and_types() {
        assert_eq!(Topic::VehicleAttitude.declared_size(), 24);
        assert_eq!(Topic::ActuatorMotors.declared_size(), 8 + 4 * ACTUATOR_MOTORS);
        assert_eq!(Topic::VehicleGlobalPosition.declared_size(), 28);
    }
}
