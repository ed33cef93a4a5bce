//! Mouse and keys → camera moves and actions. Events egui used are never
//! seen here (see `Session::on_window_event`).

use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{KeyCode, PhysicalKey};

use super::camera::{CameraRig, FlyKeys};
use super::panel::Action;

/// Pixels of a touchpad's scroll that make one wheel step.
const PIXELS_PER_STEP: f64 = 40.0;

/// What one key press asks for, beyond moving the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// One of the overlay's actions.
    Action(Action),
    /// Show or hide the overlay (Tab).
    ToggleOverlay,
    /// Close the window (Escape).
    Quit,
}

/// Buttons and keys held, and where the pointer was.
#[derive(Debug, Default)]
pub struct Input {
    orbiting: bool,
    looking: bool,
    cursor: Option<(f64, f64)>,
    held: [bool; 6],
}

const FLY_KEYS: [KeyCode; 6] = [
    KeyCode::KeyW,
    KeyCode::KeyS,
    KeyCode::KeyD,
    KeyCode::KeyA,
    KeyCode::KeyE,
    KeyCode::KeyQ,
];

/// The keys that act on the window and the camera rather than on a widget:
/// R, P, F12, Tab, Escape and the fly keys.
const WINDOW_KEYS: [KeyCode; 6] = [
    KeyCode::Space,
    KeyCode::KeyR,
    KeyCode::KeyP,
    KeyCode::F12,
    KeyCode::Tab,
    KeyCode::Escape,
];

/// Whether `event` is a press or release of one of the window's keys
/// (which work whatever widget of the overlay has the focus).
pub fn is_window_key(event: &WindowEvent) -> bool {
    let WindowEvent::KeyboardInput { event, .. } = event else {
        return false;
    };
    let PhysicalKey::Code(code) = event.physical_key else {
        return false;
    };
    WINDOW_KEYS.contains(&code) || FLY_KEYS.contains(&code)
}

/// Whether `event` is a press or release of a window key that types
/// nothing (F12, Tab): those act even while a value field is being typed
/// in, where the letter keys go to the field and Escape leaves it.
pub fn acts_while_typing(event: &WindowEvent) -> bool {
    let WindowEvent::KeyboardInput { event, .. } = event else {
        return false;
    };
    matches!(
        event.physical_key,
        PhysicalKey::Code(KeyCode::F12 | KeyCode::Tab)
    )
}

impl Input {
    /// The fly keys held now.
    pub fn fly_keys(&self) -> FlyKeys {
        let axis = |plus: usize, minus: usize| {
            f64::from(u8::from(self.held[plus])) - f64::from(u8::from(self.held[minus]))
        };
        FlyKeys {
            forward: axis(0, 1),
            right: axis(2, 3),
            up: axis(4, 5),
        }
    }

    /// Applies a window event egui did not use to `rig`; returns what a
    /// key asked for. `pointer_free` is false while the pointer is over the
    /// overlay (a press there starts no drag).
    pub fn on_event(
        &mut self,
        event: &WindowEvent,
        rig: &mut CameraRig,
        pointer_free: bool,
    ) -> Option<Command> {
        match event {
            WindowEvent::MouseInput { state, button, .. } => {
                let down = *state == ElementState::Pressed && pointer_free;
                match button {
                    MouseButton::Left => self.orbiting = down,
                    MouseButton::Right => self.looking = down,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let p = (position.x, position.y);
                if let Some(last) = self.cursor {
                    let (dx, dy) = (p.0 - last.0, p.1 - last.1);
                    if self.orbiting {
                        rig.orbit(dx, dy);
                    } else if self.looking {
                        rig.look(dx, dy);
                    }
                }
                self.cursor = Some(p);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } if pointer_free => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(*y),
                    MouseScrollDelta::PixelDelta(p) => p.y / PIXELS_PER_STEP,
                };
                rig.zoom(steps);
            }
            WindowEvent::Focused(false) => *self = Input::default(),
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return None;
                };
                let pressed = event.state == ElementState::Pressed;
                if let Some(i) = FLY_KEYS.iter().position(|&k| k == code) {
                    self.held[i] = pressed;
                    return None;
                }
                if !pressed || event.repeat {
                    return None;
                }
                return match code {
                    KeyCode::KeyR => Some(Command::Action(Action::ResetCamera)),
                    KeyCode::KeyP => Some(Command::Action(Action::TogglePath)),
                    KeyCode::Space => Some(Command::Action(Action::ToggleAnimation)),
                    KeyCode::F12 => Some(Command::Action(Action::Screenshot)),
                    KeyCode::Tab => Some(Command::ToggleOverlay),
                    KeyCode::Escape => Some(Command::Quit),
                    _ => None,
                };
            }
            _ => {}
        }
        None
    }
}
