//! A batch of commands parsed from JSON, counted as it is parsed: `POST /scenes/{scene}/commands`
//! and the stream's `commands` message.

use std::cell::Cell;
use std::fmt;

use raystage_service::Error;
use raystage_service::model::{Command, Commands};
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::extract::parse_json_seed;

/// Parses a batch, counting its commands as they are parsed: the one past `max` ends parsing
/// with 413 naming `max_commands`, so that a huge batch costs the memory of `max` commands and
/// not of all it holds. As a stream's `commands` `message`, it also takes the message's `type`
/// and its `request` number, which it returns.
pub(crate) fn parse_commands(bytes: &[u8], max: usize, message: bool) -> raystage_service::Result<(Commands, Option<u64>)> {
    let over = Cell::new(false);
    parse_json_seed(bytes, CommandsSeed { max, over: &over, message }).map_err(|e| {
        if over.get() { Error::too_large(Some("commands".into()), format!("more than {max} commands: the limit is {max}")).limit("max_commands") } else { e }
    })
}

/// Reads `{"commands": [...]}` as [`Commands`] does (or, for a stream `message`, also its
/// `"type": "commands"` and `request`), with at most `max` commands; sets `over` when there are
/// more.
#[derive(Clone, Copy)]
struct CommandsSeed<'a> {
    max: usize,
    over: &'a Cell<bool>,
    message: bool,
}

impl<'de> DeserializeSeed<'de> for CommandsSeed<'_> {
    type Value = (Commands, Option<u64>);

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Self::Value, D::Error> {
        deserializer.deserialize_struct("Commands", &["commands"], self)
    }
}

impl<'de> Visitor<'de> for CommandsSeed<'_> {
    type Value = (Commands, Option<u64>);

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an object with a `commands` array")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let (mut commands, mut request) = (None, None);
        while let Some(field) = map.next_key_seed(FieldSeed { message: self.message })? {
            match field {
                Field::Commands if commands.is_some() => return Err(de::Error::duplicate_field("commands")),
                Field::Commands => commands = Some(map.next_value_seed(CommandList(self))?),
                Field::Request => request = map.next_value::<Option<u64>>()?,
                Field::Type => {
                    let kind: String = map.next_value()?;
                    if kind != "commands" {
                        return Err(de::Error::invalid_value(de::Unexpected::Str(&kind), &"\"commands\""));
                    }
                }
            }
        }
        Ok((Commands { commands: commands.ok_or_else(|| de::Error::missing_field("commands"))? }, request))
    }
}

/// A key of a batch: `commands`, and for a stream message also `type` and `request`. Any other
/// is refused while the key is read, as the derived reader does, so that the error names it.
enum Field {
    Commands,
    Type,
    Request,
}

/// Reads a [`Field`], knowing whether the batch is a stream message.
struct FieldSeed {
    message: bool,
}

impl<'de> DeserializeSeed<'de> for FieldSeed {
    type Value = Field;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Field, D::Error> {
        deserializer.deserialize_identifier(self)
    }
}

impl Visitor<'_> for FieldSeed {
    type Value = Field;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("`commands`")
    }

    fn visit_str<E: de::Error>(self, key: &str) -> Result<Field, E> {
        match key {
            "commands" => Ok(Field::Commands),
            "type" if self.message => Ok(Field::Type),
            "request" if self.message => Ok(Field::Request),
            _ if self.message => Err(de::Error::unknown_field(key, &["type", "request", "commands"])),
            _ => Err(de::Error::unknown_field(key, &["commands"])),
        }
    }
}

/// The `commands` array of [`CommandsSeed`].
struct CommandList<'a>(CommandsSeed<'a>);

impl<'de> DeserializeSeed<'de> for CommandList<'_> {
    type Value = Vec<Command>;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Vec<Command>, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for CommandList<'_> {
    type Value = Vec<Command>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of commands")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<Command>, A::Error> {
        let CommandsSeed { max, over, .. } = self.0;
        let mut commands = Vec::new();
        while let Some(command) = seq.next_element::<Command>()? {
            if commands.len() == max {
                over.set(true);
                return Err(de::Error::custom(format_args!("more than {max} commands")));
            }
            commands.push(command);
        }
        Ok(commands)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::parse_json;

    #[test]
    fn a_batch_parses_as_the_derived_reader_would_within_the_limit() {
        let bodies = [
            r#"{"commands": [{"set_camera": {}}, {"delete_object": {"id": 3}}]}"#,
            r#"{"commands": []}"#,
            r#"{"commands": [], "also": 1}"#,
            r#"{"commands": [], "commands": []}"#,
            r#"{}"#,
            r#"[]"#,
            r#"{"commands": {}}"#,
            r#"{"commands": [{"set_camera": {"eye": [0, 0, "far"]}}]}"#,
            r#"{"commands": [{"set_camera": {"eye": [0, NaN, 1]}}]}"#,
            r#"{"commands": [{"set_camera": {}}] trailing"#,
        ];
        for body in bodies {
            let ours = parse_commands(body.as_bytes(), 10, false).map(|(c, _)| format!("{:?}", c.commands));
            let derived = parse_json::<Commands>(body.as_bytes()).map(|c| format!("{:?}", c.commands));
            assert_eq!(ours.map_err(|e| (e.kind, e.detail.field)), derived.map_err(|e| (e.kind, e.detail.field)), "{body}");
        }
    }
}
