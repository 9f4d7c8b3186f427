//! Checks a hopnav channel's schema name (`hopnav.PoseEstimate.v2`,
//! `hopnav.CloudHeader.v1+hopnav.FeaturePoint.v1[]`, `hopnav.ImageHeader.v1+u8[]`) against
//! the layouts this build reads ([`hopnav_ipc::wire::LAYOUT_VERSIONS`]).

use hopnav_ipc::wire;

use super::InspectError;

/// Whether this build reads the messages of channel `topic` with schema `schema`.
pub fn check(topic: &str, schema: &str) -> Result<(), InspectError> {
    let unknown = || InspectError::UnknownSchema {
        topic: topic.to_owned(),
        schema: schema.to_owned(),
    };
    let (header, element) = match schema.split_once('+') {
        Some((header, slice)) => (header, Some(slice.strip_suffix("[]").ok_or_else(unknown)?)),
        None => (schema, None),
    };
    for part in std::iter::once(header).chain(element.filter(|element| *element != "u8")) {
        let (type_name, recorded_version) = parse(part).ok_or_else(unknown)?;
        let current_version = wire::LAYOUT_VERSIONS
            .iter()
            .find(|(name, _)| *name == type_name)
            .map(|&(_, version)| version)
            .ok_or_else(unknown)?;
        if recorded_version != current_version {
            return Err(InspectError::OtherVersion {
                topic: topic.to_owned(),
                schema: schema.to_owned(),
                type_name: type_name.to_owned(),
                recorded_version,
                current_version,
            });
        }
    }
    Ok(())
}

/// `hopnav.<Type>.v<N>` as its type and layout version.
fn parse(name: &str) -> Option<(&str, u32)> {
    let (type_name, version) = name.strip_prefix("hopnav.")?.rsplit_once(".v")?;
    Some((type_name, version.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use hopnav_ipc::messages::{CloudHeader, FeaturePoint, ImageHeader, PoseEstimate};

    use super::*;

    #[test]
    fn this_builds_schemas_pass() {
        check("a", &wire::schema_name::<PoseEstimate>()).expect("pose");
        check("b", &wire::slice_schema_name::<ImageHeader, u8>()).expect("image");
        check("c", &wire::slice_schema_name::<CloudHeader, FeaturePoint>()).expect("cloud");
    }

    #[test]
    fn another_layout_version_is_named_with_both_versions() {
        let error = check("hopnav/rover_vo/pose", "hopnav.PoseEstimate.v1").expect_err("v1");
        assert!(
            matches!(
                &error,
                InspectError::OtherVersion { type_name, recorded_version: 1, current_version: 2, .. }
                    if type_name == "PoseEstimate"
            ),
            "{error}"
        );
        let error = check("c", "hopnav.CloudHeader.v1+hopnav.FeaturePoint.v9[]").expect_err("v9");
        assert!(
            error.to_string().contains("FeaturePoint layout v9"),
            "{error}"
        );
    }

    #[test]
    fn unknown_or_malformed_names_are_unknown_schemas() {
        for schema in [
            "hopnav.Teapot.v1",
            "hopnav.PoseEstimate",
            "hopnav.PoseEstimate.vx",
            "PoseEstimate.v2",
            "hopnav.ImageHeader.v1+u8",
            "",
        ] {
            let error = check("t", schema).expect_err(schema);
            assert!(
                matches!(error, InspectError::UnknownSchema { .. }),
                "{schema}: {error}"
            );
        }
    }
}
