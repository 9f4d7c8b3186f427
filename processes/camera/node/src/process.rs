//! The camera's lifecycle: build the scene and renderers in `prepare` (ahead of need in a warm
//! standby), open the ports in `new`, render into loaned samples in `step`.

use hopnav_ipc::messages::{
    BodyStates, CameraIntrinsics, FrameTick, ImageHeader, PixelFormat, Pose3, Robot,
};
use hopnav_ipc::process_loop::{Prepared, Process, ProcessContext, ProcessIdentity, take_prepared};
use hopnav_ipc::stamp::monotonic_now_ns;
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SlicePublisher, Subscriber};
use hopnav_world::World;
use hopnav_world::camera::PinholeCamera;
use hopnav_world::raster::{RenderScene, Renderer};
use nalgebra::Isometry3;

use hopnav_camera::{CameraSection, check_world_section};

use crate::CameraError;

/// Renders both robots' cameras every frame.
pub struct CameraProcess {
    scene: RenderScene,
    jumper_renderer: Renderer,
    rover_renderer: Renderer,
    jumper_body_from_camera: Isometry3<f64>,
    rover_body_from_left: Isometry3<f64>,
    rover_baseline_m: f64,
    body_states: Subscriber<BodyStates>,
    jumper_images: SlicePublisher<ImageHeader>,
    rover_stereo: SlicePublisher<ImageHeader>,
    frames_without_poses: u64,
}

fn intrinsics(camera: &PinholeCamera) -> CameraIntrinsics {
    CameraIntrinsics {
        fx_px: camera.fx_px,
        fy_px: camera.fy_px,
        cx_px: camera.cx_px,
        cy_px: camera.cy_px,
    }
}

fn header(
    camera: &PinholeCamera,
    body_from_camera: &Isometry3<f64>,
    robot: Robot,
    view_count: u32,
    states: &BodyStates,
) -> ImageHeader {
    let mut header = ImageHeader {
        intrinsics: intrinsics(camera),
        body_from_camera: Pose3::from_isometry(body_from_camera),
        width_px: camera.width_px,
        height_px: camera.height_px,
        stride_bytes: camera.width_px,
        format: PixelFormat::Mono8.code(),
        view_count,
        robot: robot.code(),
        ..ImageHeader::default()
    };
    header.stamp.frame_index = states.stamp.frame_index;
    header.stamp.sim_time_ns = states.stamp.sim_time_ns;
    header
}

/// What the camera builds from the configuration alone, before it has any port.
struct Scene {
    section: CameraSection,
    scene: RenderScene,
    jumper_renderer: Renderer,
    rover_renderer: Renderer,
}

impl Scene {
    fn build(config_path: &std::path::Path) -> Result<Self, CameraError> {
        let config = hopnav_config::load_file(config_path)?;
        let section = CameraSection::from_config(&config)?;
        let world = World::generate(&check_world_section(&config)?).map_err(CameraError::own)?;
        let scene = RenderScene::new(&world).map_err(CameraError::own)?;
        let map_config =
            |error| CameraError::Config(hopnav_camera::from_world_error(error, "camera"));
        let mut jumper_renderer = Renderer::with_prefix(
            &section.jumper,
            &section.render,
            "camera.jumper",
            "camera.render",
        )
        .map_err(map_config)?;
        let mut rover_renderer = Renderer::with_prefix(
            &section.rover,
            &section.render,
            "camera.rover",
            "camera.render",
        )
        .map_err(map_config)?;
        jumper_renderer.prepare(&scene);
        rover_renderer.prepare(&scene);
        Ok(Self {
            section,
            scene,
            jumper_renderer,
            rover_renderer,
        })
    }
}

impl Process for CameraProcess {
    type Error = CameraError;

    /// The world, its render scene (baked textures) and both renderers: the slow part of the
    /// start-up, which depends on the configuration only (a warm standby does it ahead).
    fn prepare(identity: &ProcessIdentity) -> Result<Prepared, CameraError> {
        Ok(Prepared::new(Scene::build(&identity.config_path)?))
    }

    fn new(context: &ProcessContext) -> Result<Self, CameraError> {
        let prepared = match take_prepared::<Scene>() {
            Some(scene) => scene,
            None => Scene::build(&context.identity.config_path)?,
        };
        let Scene {
            section,
            scene,
            jumper_renderer,
            rover_renderer,
        } = prepared;
        let jumper_len = section.jumper.width_px as usize * section.jumper.height_px as usize;
        let rover_len = 2 * section.rover.width_px as usize * section.rover.height_px as usize;
        // The mount is the pair's midpoint; the left camera sits half a baseline to the left.
        let rover_body_from_left = section
            .rover_mount
            .body_from_left_camera(section.rover_baseline_m);
        Ok(Self {
            jumper_body_from_camera: section.jumper_mount.body_from_camera(),
            rover_body_from_left,
            rover_baseline_m: section.rover_baseline_m,
            body_states: Subscriber::open(&context.node, &topics::BODY_STATES)?,
            jumper_images: SlicePublisher::open(&context.node, &topics::JUMPER_IMAGE, jumper_len)?,
            rover_stereo: SlicePublisher::open(&context.node, &topics::ROVER_STEREO, rover_len)?,
            scene,
            jumper_renderer,
            rover_renderer,
            frames_without_poses: 0,
        })
    }

    fn step(&mut self, _context: &ProcessContext, tick: &FrameTick) -> Result<(), CameraError> {
        let Some(states) = self.body_states.receive_latest()? else {
            // Physics did not publish (it is down in a real-time run): nothing true to draw.
            self.frames_without_poses += 1;
            return Ok(());
        };
        if states.stamp.frame_index != tick.stamp.frame_index {
            self.frames_without_poses += 1;
        }
        let noise_key = states.stamp.frame_index;

        let world_from_jumper_camera =
            states.jumper.world_from_body.to_isometry() * self.jumper_body_from_camera;
        let camera = *self.jumper_renderer.camera();
        let jumper_mount = self.jumper_body_from_camera;
        let renderer = &mut self.jumper_renderer;
        let scene = &self.scene;
        let len = camera.width_px as usize * camera.height_px as usize;
        self.jumper_images.send_with(len, |image_header, pixels| {
            let started_ns = monotonic_now_ns();
            renderer.render(
                scene,
                &world_from_jumper_camera,
                noise_key,
                pixels,
                camera.width_px as usize,
            )?;
            *image_header = header(&camera, &jumper_mount, Robot::Jumper, 1, &states);
            image_header.fill_time_ns = monotonic_now_ns().saturating_sub(started_ns);
            Ok::<(), hopnav_world::RenderError>(())
        })?;

        let world_from_left =
            states.rover.world_from_body.to_isometry() * self.rover_body_from_left;
        let camera = *self.rover_renderer.camera();
        let rover_mount = self.rover_body_from_left;
        let renderer = &mut self.rover_renderer;
        let view_len = camera.width_px as usize * camera.height_px as usize;
        let baseline_m = self.rover_baseline_m;
        self.rover_stereo
            .send_with(2 * view_len, |image_header, pixels| {
                let started_ns = monotonic_now_ns();
                let (left, right) = pixels.split_at_mut(view_len);
                renderer.render_stereo(
                    scene,
                    &world_from_left,
                    baseline_m,
                    noise_key,
                    left,
                    right,
                    camera.width_px as usize,
                )?;
                *image_header = header(&camera, &rover_mount, Robot::Rover, 2, &states);
                image_header.baseline_m = baseline_m;
                image_header.fill_time_ns = monotonic_now_ns().saturating_sub(started_ns);
                Ok::<(), hopnav_world::RenderError>(())
            })?;
        Ok(())
    }

    fn rejected_samples(&self) -> u64 {
        self.body_states.rejected().total()
    }

    fn stop(&mut self, context: &ProcessContext) {
        if self.frames_without_poses > 0 {
            eprintln!(
                "[{}] {} frames had no body states for their frame index",
                context.identity.name, self.frames_without_poses
            );
        }
    }
}
