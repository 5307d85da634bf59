//! A second software device with a rasteriser of its own: Mesa's llvmpipe
//! on EGL's device platform, handed to wgpu as an external GL context.
//!
//! Mesa's llvmpipe has one rasteriser per screen, and one screen per EGL
//! display: every context of a display queues its scenes on that one
//! rasteriser under one lock (`lp_setup_rasterize_scene`), so two devices
//! opened by wgpu (both on the surfaceless display) still draw one frame
//! after the other. Mesa has a second display that a process can open
//! without a window system: the *software device* of `EGL_EXT_device_enumeration`
//! (`EGL_MESA_device_software`) on the device platform
//! (`EGL_EXT_platform_device`). Its screen is another llvmpipe with its own
//! rasteriser, so frames drawn on it and on wgpu's own device are
//! rasterised at the same time.
//!
//! wgpu opens only the surfaceless display itself, so this module opens the
//! device display, creates a context like the one wgpu creates (desktop
//! OpenGL 3.3 core with robust access when the display offers OpenGL,
//! OpenGL ES 3 otherwise) and gives it to wgpu with
//! `wgpu::hal::gles::Adapter::new_external`, with the sRGB encoding of
//! sRGB targets turned on as wgpu does for its own (without it the second
//! device's frames came out in linear light, far darker). wgpu does not
//! make such a context current: every call into the device must be made
//! inside [`EglContext::enter`], which makes the context current on the
//! calling thread for as long as its guard lives, one thread at a time. A
//! wgpu object of this device dropped outside it is not freed (its GL
//! calls find no context and do nothing): the drawers drop their renderers
//! inside it, and the error paths that do not leave a few objects to the
//! end of the process. The display and the context live as long as the
//! process.

use super::RenderError;
use khronos_egl as egl;
use std::ffi::c_void;
use std::sync::{Mutex, MutexGuard};

/// `EGL_PLATFORM_DEVICE_EXT`.
const PLATFORM_DEVICE: egl::Enum = 0x313F;
/// `EGL_CONTEXT_OPENGL_ROBUST_ACCESS` (EGL 1.5).
const CONTEXT_OPENGL_ROBUST_ACCESS: egl::Int = 0x31B2;
/// `GL_FRAMEBUFFER_SRGB`.
const GL_FRAMEBUFFER_SRGB: u32 = 0x8DB9;
/// The extension a software device names among its own.
const SOFTWARE_DEVICE_EXTENSION: &str = "EGL_MESA_device_software";

type Egl = egl::DynamicInstance<egl::EGL1_5>;
type QueryDevices = unsafe extern "system" fn(egl::Int, *mut *mut c_void, *mut egl::Int) -> u32;
type QueryDeviceString = unsafe extern "system" fn(*mut c_void, egl::Int) -> *const i8;

/// An EGL context on the software device's display, made current by
/// [`EglContext::enter`].
pub(crate) struct EglContext {
    egl: Egl,
    display: egl::Display,
    context: egl::Context,
    /// Held while the context is current on some thread.
    current: Mutex<()>,
}

// SAFETY: EGL handles are plain pointers valid on any thread; the context is
// made current on one thread at a time, under `current`.
unsafe impl Send for EglContext {}
unsafe impl Sync for EglContext {}

/// The context current on this thread until dropped.
pub(crate) struct CurrentContext<'a> {
    context: &'a EglContext,
    _lock: MutexGuard<'a, ()>,
}

impl Drop for CurrentContext<'_> {
    fn drop(&mut self) {
        let _ = self
            .context
            .egl
            .make_current(self.context.display, None, None, None);
    }
}

impl EglContext {
    /// A context on Mesa's software device, or `None` when libEGL has no
    /// device platform or no software device (another driver, another
    /// EGL): then there is no second rasteriser to gain.
    pub fn open_software_device() -> Result<Option<EglContext>, RenderError> {
        // SAFETY: loads the system's libEGL, as wgpu itself does.
        let Ok(egl) = (unsafe { Egl::load_required() }) else {
            return Ok(None);
        };
        let client_extensions = egl
            .query_string(None, egl::EXTENSIONS)
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        if !client_extensions.contains("EGL_EXT_platform_device")
            || !client_extensions.contains("EGL_EXT_device_enumeration")
        {
            return Ok(None);
        }
        let Some(device) = software_device(&egl) else {
            return Ok(None);
        };
        let failed = |what: &str, error: egl::Error| RenderError::Device {
            adapter: "llvmpipe on EGL's software device".into(),
            message: format!("{what}: {error}"),
        };
        // SAFETY: `device` came from eglQueryDevicesEXT.
        let display =
            unsafe { egl.get_platform_display(PLATFORM_DEVICE, device, &[egl::ATTRIB_NONE]) }
                .map_err(|e| failed("opening the display", e))?;
        egl.initialize(display)
            .map_err(|e| failed("initialising the display", e))?;
        let config = egl
            .choose_first_config(
                display,
                &[
                    egl::SURFACE_TYPE,
                    egl::PBUFFER_BIT,
                    egl::RENDERABLE_TYPE,
                    egl::OPENGL_ES2_BIT,
                    egl::ALPHA_SIZE,
                    8,
                    egl::NONE,
                ],
            )
            .map_err(|e| failed("choosing a configuration", e))?
            .ok_or_else(|| RenderError::Device {
                adapter: "llvmpipe on EGL's software device".into(),
                message: "no off-screen configuration".into(),
            })?;
        let offers_opengl = egl
            .query_string(Some(display), egl::CLIENT_APIS)
            .map(|apis| apis.to_string_lossy().split(' ').any(|api| api == "OpenGL"))
            .unwrap_or(false);
        let (api, version) = if offers_opengl {
            (
                egl::OPENGL_API,
                [egl::CONTEXT_MAJOR_VERSION, 3, egl::CONTEXT_MINOR_VERSION, 3],
            )
        } else {
            (
                egl::OPENGL_ES_API,
                [egl::CONTEXT_MAJOR_VERSION, 3, egl::NONE, egl::NONE],
            )
        };
        egl.bind_api(api)
            .map_err(|e| failed("choosing the client API", e))?;
        let mut attributes: Vec<egl::Int> = version
            .into_iter()
            .take_while(|&attribute| attribute != egl::NONE)
            .collect();
        attributes.extend([
            CONTEXT_OPENGL_ROBUST_ACCESS,
            egl::TRUE as egl::Int,
            egl::NONE,
        ]);
        let context = egl
            .create_context(display, config, None, &attributes)
            .map_err(|e| failed("creating the context", e))?;
        Ok(Some(EglContext {
            egl,
            display,
            context,
            current: Mutex::new(()),
        }))
    }

    /// Makes the context current on this thread until the guard drops
    /// (waiting while another thread has it).
    pub fn enter(&self) -> CurrentContext<'_> {
        let lock = self
            .current
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        self.egl
            .make_current(self.display, None, None, Some(self.context))
            .expect("an EGL context that was made current once can be again");
        CurrentContext {
            context: self,
            _lock: lock,
        }
    }

    /// The address of a GL function, for wgpu's loader (inside [`EglContext::enter`]).
    pub fn proc_address(&self, name: &str) -> *const c_void {
        self.egl
            .get_proc_address(name)
            .map_or(std::ptr::null(), |f| f as *const c_void)
    }

    /// Turns on the sRGB encoding of what is drawn into sRGB targets, as
    /// wgpu does for the contexts it makes (desktop OpenGL leaves it off;
    /// OpenGL ES always encodes). Inside [`EglContext::enter`].
    pub fn enable_srgb_writes(&self) {
        type Enable = unsafe extern "system" fn(u32);
        if let Some(enable) = self.egl.get_proc_address("glEnable") {
            // SAFETY: glEnable's signature; the context is current.
            let enable: Enable = unsafe { std::mem::transmute(enable) };
            unsafe { enable(GL_FRAMEBUFFER_SRGB) };
        }
    }
}

/// Mesa's software device, if libEGL lists one.
fn software_device(egl: &Egl) -> Option<*mut c_void> {
    let query_devices: QueryDevices =
        unsafe { std::mem::transmute(egl.get_proc_address("eglQueryDevicesEXT")?) };
    let query_string: QueryDeviceString =
        unsafe { std::mem::transmute(egl.get_proc_address("eglQueryDeviceStringEXT")?) };
    let mut devices = [std::ptr::null_mut(); 16];
    let mut count = 0;
    // SAFETY: the buffer holds as many devices as it says.
    if unsafe { query_devices(devices.len() as egl::Int, devices.as_mut_ptr(), &mut count) } == 0 {
        return None;
    }
    devices[..count.max(0) as usize]
        .iter()
        .copied()
        .find(|&device| {
            // SAFETY: a listed device; the string is libEGL's, NUL-terminated.
            let extensions = unsafe { query_string(device, egl::EXTENSIONS) };
            !extensions.is_null()
                && unsafe { std::ffi::CStr::from_ptr(extensions) }
                    .to_string_lossy()
                    .split(' ')
                    .any(|extension| extension == SOFTWARE_DEVICE_EXTENSION)
        })
}
