//! The actions a failsafe parameter chooses between, as enums with PX4's codes: `NAV_DLL_ACT`
//! (GCS link loss), `NAV_RCL_ACT` (stick loss), `COM_RC_IN_MODE` (stick sources),
//! `COM_OBL_RC_ACT` (offboard loss), `GF_ACTION` (geofence breach), `COM_LOW_BAT_ACT`
//! (battery) and `COM_ACT_FAIL_ACT` (motor failure); and the destinations a return may choose (`RTL_TYPE`). Each converts from its
//! code with [`TryFrom<i32>`], refusing codes
//! PX4 does not define, and back with `From<_> for i32` / `f64`. Pure.

use thiserror::Error;

/// A code that names no action of a parameter.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{value} is not a {param} action (choose {choices})")]
pub struct UnknownAction {
    /// The parameter (`NAV_DLL_ACT`, ...).
    pub param: &'static str,
    /// The refused code.
    pub value: i32,
    /// The codes it accepts with their meanings, e.g. `0 disabled, 1 hold`.
    pub choices: String,
}

/// Declares an action enum: variants with their PX4 codes and one-word meanings, the default,
/// `TryFrom<i32>` (refusing other codes with [`UnknownAction`]) and `From<_>` for `i32` and `f64`.
macro_rules! action_enum {
    (
        $(#[$meta:meta])*
        $name:ident, $param:literal, default $default:ident {
            $($(#[$vmeta:meta])* $variant:ident = $code:literal, $label:literal;)+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[$vmeta])* $variant = $code,)+
        }

        impl $name {
            /// The parameter this action is the value of.
            pub const PARAM: &'static str = $param;
            /// Every action, by code.
            pub const ALL: &'static [Self] = &[$(Self::$variant),+];

            /// The meaning of the action in a word or two.
            pub fn label(self) -> &'static str {
                match self {
                    $(Self::$variant => $label,)+
                }
            }

            /// Every code with its meaning, by code.
            pub fn codes() -> Vec<(i32, &'static str)> {
                Self::ALL.iter().map(|a| (i32::from(*a), a.label())).collect()
            }

            /// Every code with its meaning: `0 disabled, 1 hold, ...`.
            pub fn choices() -> String {
                let all: Vec<String> = Self::codes().iter().map(|(c, l)| format!("{c} {l}")).collect();
                all.join(", ")
            }
        }

        impl Default for $name {
            fn default() -> Self {
                Self::$default
            }
        }

        impl TryFrom<i32> for $name {
            type Error = UnknownAction;

            fn try_from(value: i32) -> Result<Self, UnknownAction> {
                match value {
                    $($code => Ok(Self::$variant),)+
                    _ => Err(UnknownAction {
                        param: $param,
                        value,
                        choices: Self::choices(),
                    }),
                }
            }
        }

        impl From<$name> for i32 {
            fn from(action: $name) -> i32 {
                action as i32
            }
        }

        impl From<$name> for f64 {
            fn from(action: $name) -> f64 {
                f64::from(action as i32)
            }
        }
    };
}

action_enum! {
    /// What the vehicle does when the GCS link is lost in flight (`NAV_DLL_ACT`; PX4 has no 4).
    LinkLossAction, "NAV_DLL_ACT", default Disabled {
        /// Nothing.
        Disabled = 0, "disabled";
        /// Hold position (AUTO.LOITER).
        Hold = 1, "hold";
        /// Return to launch.
        Return = 2, "return";
        /// Land here.
        Land = 3, "land";
        /// Flight termination: motors off.
        Terminate = 5, "terminate";
        /// Disarm: motors off.
        Disarm = 6, "disarm";
    }
}

action_enum! {
    /// What the vehicle does when the offboard setpoints stop (`COM_OBL_RC_ACT`). Without RC,
    /// the three stick modes all hold position (POSCTL), as PX4 does without sticks.
    OffboardLossAction, "COM_OBL_RC_ACT", default Position {
        /// Position mode (POSCTL).
        Position = 0, "position";
        /// Altitude mode; without RC, position mode.
        Altitude = 1, "altitude";
        /// Manual mode; without RC, position mode.
        Manual = 2, "manual";
        /// Return to launch.
        Return = 3, "return";
        /// Land here.
        Land = 4, "land";
        /// Hold position (AUTO.LOITER).
        Hold = 5, "hold";
        /// Flight termination: motors off.
        Terminate = 6, "terminate";
        /// Disarm: motors off.
        Disarm = 7, "disarm";
    }
}

action_enum! {
    /// What the loss of the sticks does (`NAV_RCL_ACT`; the codes of `NAV_DLL_ACT`).
    ManualLossAction, "NAV_RCL_ACT", default Return {
        /// Nothing; a stick mode that cannot fly without sticks holds position.
        Disabled = 0, "disabled";
        /// Hold position (AUTO.LOITER).
        Hold = 1, "hold";
        /// Return to launch.
        Return = 2, "return";
        /// Land here.
        Land = 3, "land";
        /// Flight termination: motors off.
        Terminate = 5, "terminate";
        /// Disarm: motors off.
        Disarm = 6, "disarm";
    }
}

action_enum! {
    /// Which stick sources the vehicle flies (`COM_RC_IN_MODE`). This vehicle has no RC
    /// receiver: MANUAL_CONTROL is its only source.
    ManualInputMode, "COM_RC_IN_MODE", default KeepFirst {
        /// RC only: MANUAL_CONTROL is ignored.
        RcOnly = 0, "RC only";
        /// MAVLink only.
        MavlinkOnly = 1, "MAVLink only";
        /// RC or MAVLink, the other when one stops.
        Fallback = 2, "RC or MAVLink with fallback";
        /// RC or MAVLink, the first one heard is kept.
        KeepFirst = 3, "RC or MAVLink, keep first";
        /// No stick input at all.
        Disabled = 4, "disabled";
    }
}

impl From<ManualLossAction> for LinkLossAction {
    fn from(action: ManualLossAction) -> Self {
        match action {
            ManualLossAction::Disabled => Self::Disabled,
            ManualLossAction::Hold => Self::Hold,
            ManualLossAction::Return => Self::Return,
            ManualLossAction::Land => Self::Land,
            ManualLossAction::Terminate => Self::Terminate,
            ManualLossAction::Disarm => Self::Disarm,
        }
    }
}

action_enum! {
    /// What a geofence breach in flight does (`GF_ACTION`).
    GeofenceAction, "GF_ACTION", default Hold {
        /// Nothing (PX4's "none").
        Disabled = 0, "none";
        /// Announce only.
        Warn = 1, "warning";
        /// Hold position (AUTO.LOITER).
        Hold = 2, "hold";
        /// Return to launch.
        Return = 3, "return";
        /// Flight termination: motors off.
        Terminate = 4, "terminate";
        /// Land here.
        Land = 5, "land";
    }
}

action_enum! {
    /// What the critical and emergency battery levels do (`COM_LOW_BAT_ACT`; PX4 has no 1).
    LowBatteryAction, "COM_LOW_BAT_ACT", default Warn {
        /// Announce only, at every level.
        Warn = 0, "warning";
        /// Land at the critical level.
        Land = 2, "land";
        /// Return at the critical level, land at the emergency level.
        Return = 3, "return (land at emergency)";
    }
}

action_enum! {
    /// What a motor failure in flight does (`COM_ACT_FAIL_ACT`, PX4's codes and default).
    ActuatorFailureAction, "COM_ACT_FAIL_ACT", default Warn {
        /// Announce only; the vehicle flies on in its mode.
        Warn = 0, "warning";
        /// Hold position (AUTO.LOITER).
        Hold = 1, "hold";
        /// Land here.
        Land = 2, "land";
        /// Return to launch.
        Return = 3, "return";
        /// Flight termination: motors off.
        Terminate = 4, "terminate";
    }
}

action_enum! {
    /// Where AUTO.RTL returns to (`RTL_TYPE`, PX4's destination rule of `RTL::findRtlDestination`
    /// without mission landings; the mission-path types 2 and 4 are not modelled).
    RtlType, "RTL_TYPE", default HomeOrRally {
        /// Home or the closest rally point, whichever is closer.
        HomeOrRally = 0, "home or closest rally point";
        /// The closest rally point; home only when there is none.
        RallyFirst = 1, "closest rally point, else home";
        /// The closest safe destination (home or rally point; mission landings are not modelled).
        Closest = 3, "closest of home and rally points";
        /// The closest rally point; without one, land where the return started.
        RallyOnly = 5, "closest rally point, else land here";
        /// Home while the battery's time remaining reaches it, else the closest rally point
        /// (PX4 2026). The battery gauge gives no time remaining (BATTERY_STATUS reports it
        /// unknown), and then PX4 goes to the closest of home and rally points, as type 0.
        PrioritizeHome = 6, "home if reachable, else closest rally point";
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trips<A>(all: &[A], holes: &[i32])
    where
        A: Copy + PartialEq + std::fmt::Debug + TryFrom<i32, Error = UnknownAction>,
        i32: From<A>,
        f64: From<A>,
    {
        for a in all {
            assert_eq!(A::try_from(i32::from(*a)), Ok(*a));
            let code = i32::from(*a);
            assert_eq!(f64::from(*a), <f64 as From<i32>>::from(code));
        }
        for code in holes {
            let e = A::try_from(*code).unwrap_err();
            assert_eq!(e.value, *code);
        }
    }

    #[test]
    fn every_action_round_trips_and_undefined_codes_are_refused() {
        round_trips(LinkLossAction::ALL, &[-1, 4, 7]);
        round_trips(OffboardLossAction::ALL, &[-1, 8]);
        round_trips(GeofenceAction::ALL, &[-1, 6]);
        round_trips(LowBatteryAction::ALL, &[-1, 1, 4]);
        round_trips(ManualLossAction::ALL, &[-1, 4, 7]);
        round_trips(ManualInputMode::ALL, &[-1, 5]);
        for a in ManualLossAction::ALL {
            assert_eq!(i32::from(LinkLossAction::from(*a)), i32::from(*a), "same codes");
        }
        round_trips(RtlType::ALL, &[-1, 2, 4, 7]);
        round_trips(ActuatorFailureAction::ALL, &[-1, 5]);
        assert_eq!(LinkLossAction::ALL.len(), 6);
        assert_eq!(OffboardLossAction::ALL.len(), 8);
        assert_eq!(GeofenceAction::ALL.len(), 6);
        assert_eq!(LowBatteryAction::ALL.len(), 3);
    }

    #[test]
    fn refusals_name_the_value_and_the_choices() {
        let e = LinkLossAction::try_from(4).unwrap_err().to_string();
        assert_eq!(
            e,
            "4 is not a NAV_DLL_ACT action (choose 0 disabled, 1 hold, 2 return, 3 land, 5 terminate, 6 disarm)"
        );
        let e = LowBatteryAction::try_from(1).unwrap_err().to_string();
        assert!(e.starts_with("1 is not a COM_LOW_BAT_ACT action"), "{e}");
    }

    #[test]
    fn defaults_are_px4s() {
        assert_eq!(LinkLossAction::default(), LinkLossAction::Disabled);
        assert_eq!(OffboardLossAction::default(), OffboardLossAction::Position);
        assert_eq!(GeofenceAction::default(), GeofenceAction::Hold);
        assert_eq!(LowBatteryAction::default(), LowBatteryAction::Warn);
        assert_eq!(ManualLossAction::default(), ManualLossAction::Return);
        assert_eq!(ManualInputMode::default(), ManualInputMode::KeepFirst);
        assert_eq!(RtlType::default(), RtlType::HomeOrRally);
        assert_eq!(ActuatorFailureAction::default(), ActuatorFailureAction::Warn);
    }
}
